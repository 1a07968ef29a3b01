// Session: who this page is (owner or viewer), and the link that lets a second person join the
// same session (?join=<session id>&volume=<its volume>: a cluster routes by the volume).

import type GUI from 'lil-gui';
import type { SessionInfo } from '../protocol/connection';

/**
 * The address a second person opens to join `session` on `volume`. It keeps the page's other
 * parameters, the access token among them: whoever has the link may watch.
 */
export function joinLink(
  location: { origin: string; pathname: string; search: string },
  session: string,
  volume: string,
): string {
  const params = new URLSearchParams(location.search);
  params.set('join', session);
  params.set('volume', volume);
  return `${location.origin}${location.pathname}?${params.toString()}`;
}

export class SessionPanel {
  private readonly role: HTMLElement;
  private readonly link: HTMLInputElement;
  private readonly copy: HTMLButtonElement;

  constructor(folder: GUI) {
    const root = document.createElement('div');
    root.className = 'session-panel';
    this.role = document.createElement('div');
    this.role.className = 'role';
    this.role.textContent = 'no session yet';
    const row = document.createElement('div');
    row.className = 'share-row';
    this.link = document.createElement('input');
    this.link.id = 'share-link';
    this.link.readOnly = true;
    this.link.placeholder = 'share link';
    this.link.addEventListener('focus', () => this.link.select());
    this.copy = document.createElement('button');
    this.copy.textContent = 'Copy';
    this.copy.addEventListener('click', () => {
      this.link.select();
      void navigator.clipboard?.writeText(this.link.value).then(
        () => (this.copy.textContent = 'Copied'),
        () => (this.copy.textContent = 'Select + copy'),
      );
      setTimeout(() => (this.copy.textContent = 'Copy'), 2000);
    });
    row.append(this.link, this.copy);
    const hint = document.createElement('div');
    hint.className = 'hint';
    hint.textContent = 'Anyone with this link sees the same frames (read-only).';
    root.append(this.role, row, hint);
    folder.$children.appendChild(root);
  }

  update(info: SessionInfo): void {
    this.role.dataset['role'] = info.role;
    this.role.textContent =
      info.role === 'owner'
        ? `You control session ${info.session.slice(0, 8)}… (${info.volume.name})`
        : `Viewing session ${info.session.slice(0, 8)}… (${info.volume.name}), read-only`;
    this.link.value = joinLink(window.location, info.session, info.volume.id);
  }
}
