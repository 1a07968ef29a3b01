// How a panel offers a number the server's hello announces a range for (hello.ranges): a slider
// spanning the range, or a free number field where a slider cannot reach the low end. The method
// panel offers those under `settings/`, the light control those under `light/`. No DOM here.

import type { SettingRange, SettingRanges } from '../protocol/messages';

/** How one numeric setting of hello.ranges is offered. */
export interface SettingControl {
  /** Its path in a `set` patch: settings/light_buffer/compensation. */
  path: string;
  /** The members under the part of the state it is in: ['light_buffer', 'compensation']. */
  members: string[];
  /** The folder it goes in: the first of several members ('light_buffer'), else ''. */
  part: string;
  label: string;
  /** What it does and the values it takes, as the control's hint. */
  hint: string;
  /**
   * `slider`: spans the range (whole numbers where the range says so). `number`: a free number
   * field, for a range over many decades above zero (distances such as the sample distance), which
   * a linear slider cannot reach the low end of; the server checks it and says what is wrong.
   */
  kind: 'slider' | 'number';
  min: number;
  max: number;
  integer: boolean;
  /** Decimals a number field shows: enough for the range's low end. */
  decimals: number;
}

/** A range whose ends lie this many times apart (above zero) gets a number field, not a slider. */
const DECADES_FOR_A_NUMBER_FIELD = 1e4;

export function labelOf(member: string): string {
  return member.replace(/_/g, ' ');
}

/** How a range reads in a hint: `0..16` for whole numbers, `[0, 100]` otherwise. */
export function rangeText(range: SettingRange): string {
  return range.integer ? `${range.min}..${range.max}` : `[${range.min}, ${range.max}]`;
}

/** The control of each number under `root` (`settings`, `light`) that hello.ranges announces. */
export function settingControls(ranges: SettingRanges, root: string): SettingControl[] {
  return Object.entries(ranges)
    .filter(([path]) => path.startsWith(`${root}/`))
    .map(([path, range]) => {
      const members = path.split('/').slice(1);
      const name = members[members.length - 1]!;
      const wide = range.min > 0 && range.max / range.min >= DECADES_FOR_A_NUMBER_FIELD;
      const within = rangeText(range);
      return {
        path,
        members,
        part: members.length > 1 ? members[0]! : '',
        label: labelOf(name),
        hint: range.summary ? `${range.summary}; within ${within}` : `within ${within}`,
        kind: wide && !range.integer ? 'number' : 'slider',
        min: range.min,
        max: range.max,
        integer: range.integer,
        decimals: wide ? Math.ceil(-Math.log10(range.min)) + 2 : 0,
      };
    });
}

/** The value at `members` below `part` (a state's settings or light), or undefined where none. */
export function valueAt(part: object, members: string[]): number | undefined {
  let value: unknown = part;
  for (const member of members) {
    const parent =
      typeof value === 'object' && value !== null ? (value as Record<string, unknown>) : {};
    value = parent[member];
  }
  return typeof value === 'number' ? value : undefined;
}

/** `value` nested under `members`: { light_buffer: { compensation: value } }. */
export function nestedAt(members: string[], value: unknown): Record<string, unknown> {
  let inner: unknown = value;
  for (const member of [...members].reverse()) inner = { [member]: inner };
  return inner as Record<string, unknown>;
}
