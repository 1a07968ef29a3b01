import { describe, expect, it } from 'vitest';
import { joinLink } from '../src/panels/session_panel';

describe('joinLink', () => {
  it("names the session and its volume, which a cluster's proxy routes by, and keeps the token", () => {
    const page = {
      origin: 'https://viewer.example:8443',
      pathname: '/',
      search: '?volume=old.nii&token=a%2Bb',
    };
    const link = new URL(joinLink(page, 'abc123', 'heads/ch2.nii.gz'));
    expect(link.origin).toBe('https://viewer.example:8443');
    expect(link.searchParams.get('join')).toBe('abc123');
    expect(link.searchParams.get('volume')).toBe('heads/ch2.nii.gz');
    expect(link.searchParams.get('token')).toBe('a+b');
  });
});
