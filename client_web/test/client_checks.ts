// The checks a client message gets from the server (§3-§5 at a hello's terms), for the client's
// tests: what the client sends is held against proto/examples/v1 and the server's limits, ranges,
// modes and presets as a recorded hello states them. The client itself sends what a person asked
// for and shows the server's answer.

import {
  BUILDERS,
  COMPOSITINGS,
  ENCODINGS,
  HOUNSFIELD,
  LIGHT_LOOKUPS,
  LIGHT_TYPES,
  POSITION_SPACES,
  RECONSTRUCTIONS,
  STAGES,
  VIEWS,
  type Camera,
  type ErrorCode,
  type HelloMessage,
  type Light,
  type Limits,
  type SettingRanges,
  type Vec3,
  type ViewName,
} from '../src/protocol/messages';
import type { Orbit } from '../src/interaction/orbit_camera';
import { SETTINGS } from '../src/protocol/generated/server_tables';

/** A `set`'s camera: any of the camera's members, or an orbit or a named view instead of the eye. */
type CameraPatch = Partial<Camera> & { orbit?: Orbit; view?: ViewName };

type Json = null | boolean | number | string | Json[] | { [key: string]: Json };

/** The pointer of the first container nested deeper than `limit` (the message is 1), as the server
 * reports it, or null. */
function firstBeyondDepth(value: unknown, limit: number, at = '', depth = 1): string | null {
  if (value === null || typeof value !== 'object') {
    return null;
  }
  if (depth > limit) {
    return at === '' ? '/' : at;
  }
  for (const [key, child] of Object.entries(value)) {
    const found = firstBeyondDepth(
      child,
      limit,
      `${at}/${key.replace(/~/g, '~0').replace(/\//g, '~1')}`,
      depth + 1,
    );
    if (found !== null) {
      return found;
    }
  }
  return null;
}

function isObject(value: unknown): value is Record<string, unknown> {
  return typeof value === 'object' && value !== null && !Array.isArray(value);
}

/** A problem the server would report: its error code and JSON pointer. */
export interface Problem {
  code: ErrorCode;
  field: string;
  message: string;
}

class Reject extends Error {
  constructor(readonly problem: Problem) {
    super(problem.message);
  }
}

function reject(code: ErrorCode, field: string, message: string): never {
  throw new Reject({ code, field, message });
}

type Check = (value: Json, at: string) => void;

interface Spec {
  [member: string]: Check;
}

/** The members of a part of a `set` that are no numbers with a range; nested parts as shapes. */
interface Shape {
  [member: string]: Check | Shape;
}

function members(
  value: Json,
  at: string,
  spec: Spec,
  required: string[] = [],
  missing: ErrorCode = 'invalid_message',
): void {
  if (!isObject(value)) {
    reject('invalid_value', at, 'expected an object');
  }
  const o = value as Record<string, Json>;
  for (const key of Object.keys(o)) {
    if (!(key in spec)) {
      reject('unknown_field', `${at}/${key}`, `unknown member "${key}"`);
    }
  }
  for (const key of required) {
    if (!(key in o)) {
      reject(missing, `${at}/${key}`, `missing "${key}"`);
    }
  }
  for (const [key, check] of Object.entries(spec)) {
    if (key in o) {
      check(o[key] as Json, `${at}/${key}`);
    }
  }
}

const number =
  (min: number, max: number) =>
  (value: Json, at: string): void => {
    if (typeof value !== 'number') {
      reject('invalid_value', at, 'expected a number');
    }
    if (value < min || value > max) {
      reject('out_of_range', at, `must be within [${min}, ${max}]`);
    }
  };

const integer =
  (min: number, max: number) =>
  (value: Json, at: string): void => {
    if (typeof value !== 'number' || !Number.isInteger(value)) {
      reject('invalid_value', at, 'expected an integer');
    }
    number(min, max)(value, at);
  };

const oneOf =
  (values: readonly string[]) =>
  (value: Json, at: string): void => {
    if (typeof value !== 'string' || !values.includes(value)) {
      reject('invalid_value', at, `expected one of ${values.join(', ')}`);
    }
  };

const boolean = (value: Json, at: string): void => {
  if (typeof value !== 'boolean') {
    reject('invalid_value', at, 'expected a boolean');
  }
};

const string =
  (maxBytes: number) =>
  (value: Json, at: string): void => {
    if (typeof value !== 'string') {
      reject('invalid_value', at, 'expected a string');
    }
    if (new TextEncoder().encode(value).length > maxBytes) {
      reject('out_of_range', at, `longer than ${maxBytes} bytes`);
    }
  };

const vector =
  (n: number, item: (value: Json, at: string) => void) =>
  (value: Json, at: string): void => {
    if (!Array.isArray(value) || value.length !== n) {
      reject('invalid_value', at, `expected ${n} values`);
    }
    value.forEach((v, i) => item(v, `${at}/${i}`));
  };

/**
 * A string no longer than the server takes for the member `key` (`open/volume`,
 * hello.limits.max_string_bytes); a member it announces no length for is left to it.
 */
function textOf(limits: Limits, key: string): Check {
  return string(limits.max_string_bytes[key] ?? Infinity);
}

/**
 * A number within the server's range for the setting at `path` (hello.ranges), a whole one where
 * the range says so; a server that announces no range for it judges it itself.
 */
const ranged =
  (ranges: SettingRanges, path: string) =>
  (value: Json, at: string): void => {
    const range = ranges[path];
    if (range === undefined) {
      number(-Infinity, Infinity)(value, at);
      return;
    }
    (range.integer ? integer : number)(range.min, range.max)(value, at);
  };

const coords = (ranges: SettingRanges) => vector(3, ranged(ranges, 'vec3'));
const rgb = (ranges: SettingRanges) => vector(3, ranged(ranges, 'rgb'));

/**
 * The checks of the members at `path` of a `set` (`settings`, `settings/light_buffer`): those of
 * `shape`, and for each number hello.ranges announces there the check of its range, a part that a
 * range's path names (`camera/orbit`) being checked the same way.
 */
function specAt(path: string, shape: Shape, ranges: SettingRanges): Spec {
  const spec: Spec = {};
  const parts = new Map<string, Shape>();
  for (const [member, entry] of Object.entries(shape)) {
    if (typeof entry === 'function') spec[member] = entry;
    else parts.set(member, entry);
  }
  for (const rangePath of Object.keys(ranges)) {
    if (!rangePath.startsWith(`${path}/`)) continue;
    const below = rangePath.slice(path.length + 1).split('/') as [string, ...string[]];
    const [member, ...deeper] = below;
    if (deeper.length === 0) spec[member] ??= ranged(ranges, rangePath);
    else if (!parts.has(member)) parts.set(member, {});
  }
  for (const [member, part] of parts) {
    spec[member] = (value, at) => members(value, at, specAt(`${path}/${member}`, part, ranges));
  }
  return spec;
}

function points(item: Spec, required: string[], valueKey: string, maxPoints: number) {
  return (value: Json, at: string): void => {
    if (!Array.isArray(value)) {
      reject('invalid_value', at, 'expected an array');
    }
    if (value.length > maxPoints) {
      reject('out_of_range', at, `more than ${maxPoints} points`);
    }
    value.forEach((p, i) => members(p, `${at}/${i}`, item, required, 'invalid_value'));
    for (let i = 1; i < value.length; ++i) {
      const x = (value[i] as { x: number }).x;
      if (x < (value[i - 1] as { x: number }).x) {
        reject('invalid_value', `${at}/${i}`, `positions must not decrease (${valueKey})`);
      }
    }
  };
}

function cameraSpec(ranges: SettingRanges): Spec {
  const shape = {
    eye: coords(ranges),
    target: coords(ranges),
    up: coords(ranges),
    view: oneOf(VIEWS),
  };
  return specAt('camera', shape, ranges);
}

function lightSpec(ranges: SettingRanges): Spec {
  const shape = {
    type: oneOf(LIGHT_TYPES),
    direction: coords(ranges),
    position: coords(ranges),
    color: rgb(ranges),
  };
  return specAt('light', shape, ranges);
}

const checkTransferFunction =
  (ranges: SettingRanges, limits: Limits, presets: readonly string[] | null) =>
  (value: Json, at: string): void => {
    if (isObject(value) && 'preset' in value) {
      members(value, at, { preset: presets === null ? string(Infinity) : oneOf(presets) });
      return;
    }
    const hounsfield = isObject(value) && value['space'] === HOUNSFIELD;
    const reach = limits.max_hounsfield_position;
    const x = hounsfield ? number(-reach, reach) : number(0, 1);
    const most = limits.max_transfer_function_points;
    members(value, at, {
      name: textOf(limits, 'set/transfer_function/name'),
      space: oneOf(POSITION_SPACES),
      colors: points({ x, rgb: rgb(ranges) }, ['x', 'rgb'], 'colors', most),
      opacities: points({ x, alpha: number(0, 1) }, ['x', 'alpha'], 'opacities', most),
    });
  };

function settingsSpec(
  limits: Limits,
  modes: readonly string[] | null,
  ranges: SettingRanges,
): Spec {
  return specAt(
    'settings',
    {
      mode: modes === null ? string(32) : oneOf(modes),
      compositing: oneOf(COMPOSITINGS),
      reconstruction: oneOf(RECONSTRUCTIONS),
      stage: oneOf(STAGES),
      size: vector(2, integer(1, limits.max_image_side)),
      background: rgb(ranges),
      phong: boolean,
      empty_space_skipping: boolean,
      jitter: boolean,
      preintegration: boolean,
      shading: {},
      light_buffer: {
        slices: integer(1, limits.max_slices),
        resolution: integer(1, limits.max_light_resolution),
        builder: oneOf(BUILDERS),
        lookup: oneOf(LIGHT_LOOKUPS),
      },
      scattering: {},
    },
    ranges,
  );
}

/** The cut: the crop box's corners in RAS millimetres within the server's reach, and switches. */
function cutSpec(ranges: SettingRanges): Spec {
  const corner = vector(3, number(SETTINGS['cut/crop/min'].min, SETTINGS['cut/crop/min'].max));
  const plane = {
    enabled: boolean,
    point: vector(3, number(SETTINGS['cut/plane_1/point'].min, SETTINGS['cut/plane_1/point'].max)),
    normal: vector(
      3,
      number(SETTINGS['cut/plane_1/normal'].min, SETTINGS['cut/plane_1/normal'].max),
    ),
  };
  const planes = Object.fromEntries(
    Object.keys(SETTINGS)
      .filter((path) => /^cut\/plane_\d+\/enabled$/.test(path))
      .map((path) => [path.split('/')[1]!, plane]),
  );
  return specAt(
    'cut',
    { crop: { enabled: boolean, min: corner, max: corner }, ...planes, casts_shadows: boolean },
    ranges,
  );
}

function subtract(a: Vec3, b: Vec3): Vec3 {
  return [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
}

/** What a server's hello says about the messages it takes. */
export interface ServerTerms {
  /** Its settings' ranges: which members of a `set` are numbers, and their limits. */
  ranges: SettingRanges;
  /** Its limits. */
  limits: Limits;
  /** The mode names it offers; absent or null: any name, left to the server. */
  modes?: readonly string[] | null;
  /** Its presets' names; absent or null: any name, left to the server. */
  presets?: readonly string[] | null;
}

/** The terms a server's hello states: its ranges, limits, modes and presets. */
export function termsOf(hello: HelloMessage): ServerTerms {
  return {
    ranges: hello.ranges,
    limits: hello.limits,
    modes: hello.modes.map((m) => m.name),
    presets: hello.presets.map((p) => p.name),
  };
}

/**
 * Checks a client message as the server would (§3-§5 at its limits, modes and ranges), except for
 * what needs the session's current state (eye = target after a partial camera patch). Returns null
 * when the server would accept it. The client sends what the person asked for and shows the
 * server's answer; this is for tests and for catching the client's own mistakes during
 * development.
 */
function labelsSpec(): Spec {
  const fraction = number(0, 1);
  const style: Spec = { color: vector(3, fraction), opacity: fraction, visible: boolean };
  return {
    all: (v, at) => members(v, at, { opacity: fraction, visible: boolean }),
    only: (v, at) => {
      if (!Array.isArray(v)) {
        reject('invalid_value', at, 'expected an array of label ids');
      }
      v.forEach((id, i) => {
        if (typeof id !== 'number' || !Number.isSafeInteger(id)) {
          reject('invalid_value', `${at}/${i}`, 'expected a label id');
        }
      });
    },
    styles: (v, at) => {
      if (!isObject(v)) {
        reject('invalid_value', at, 'expected an object');
      }
      for (const [id, entry] of Object.entries(v as Record<string, Json>)) {
        members(entry, `${at}/${id}`, style);
      }
    },
    blend: fraction,
    alone: boolean,
  };
}

export function checkClientMessage(value: unknown, server: ServerTerms): Problem | null {
  const { ranges, limits, modes = null, presets = null } = server;
  try {
    if (!isObject(value)) {
      reject('invalid_message', '/', 'not an object');
    }
    const tooDeep = firstBeyondDepth(value, limits.max_json_depth);
    if (tooDeep !== null) {
      reject('out_of_range', tooDeep, `nested deeper than ${limits.max_json_depth} containers`);
    }
    const o = value as Record<string, Json>;
    if (!('v' in o)) {
      reject('invalid_message', '/v', 'missing "v"');
    }
    if (o['v'] !== 1 || typeof o['v'] !== 'number') {
      reject('unsupported_version', '/v', 'only version 1');
    }
    if ('id' in o) {
      const id = o['id'];
      if (typeof id !== 'number' || !Number.isSafeInteger(id)) {
        reject('invalid_value', '/id', 'expected a 64-bit integer');
      }
    }
    if (!('type' in o)) {
      reject('invalid_message', '/type', 'missing "type"');
    }
    if (typeof o['type'] !== 'string') {
      reject('invalid_value', '/type', 'expected a string');
    }
    const envelope: Spec = { v: () => {}, type: () => {}, id: () => {} };
    switch (o['type']) {
      case 'list_volumes':
      case 'stats':
      case 'close':
        members(o, '', envelope);
        break;
      case 'open':
        members(o, '', { ...envelope, volume: textOf(limits, 'open/volume') }, ['volume']);
        break;
      case 'add_labels':
        members(o, '', { ...envelope, volume: textOf(limits, 'add_labels/volume') }, ['volume']);
        break;
      case 'remove_labels':
        members(o, '', envelope);
        break;
      case 'pick':
        members(o, '', { ...envelope, x: number(0, 1), y: number(0, 1) }, ['x', 'y']);
        break;
      case 'export': {
        const side = integer(1, limits.max_export_side);
        members(o, '', { ...envelope, width: side, height: side }, ['width', 'height']);
        break;
      }
      case 'export_movie': {
        const side = (value: Json, at: string): void => {
          integer(2, limits.max_movie_side)(value, at);
          if ((value as number) % 2 !== 0) {
            reject('invalid_value', at, "a movie's sides are even");
          }
        };
        members(
          o,
          '',
          {
            ...envelope,
            width: side,
            height: side,
            frames: integer(1, limits.max_movie_frames),
            rock: number(0, 180),
          },
          ['width', 'height', 'frames', 'rock'],
        );
        break;
      }
      case 'cancel_export':
        members(o, '', { ...envelope, export: textOf(limits, 'cancel_export/export') }, ['export']);
        break;
      case 'join':
        members(o, '', { ...envelope, session: textOf(limits, 'join/session') }, ['session']);
        break;
      case 'resume':
        members(
          o,
          '',
          {
            ...envelope,
            session: textOf(limits, 'resume/session'),
            owner_token: textOf(limits, 'resume/owner_token'),
            volume: textOf(limits, 'resume/volume'),
          },
          ['session', 'owner_token'],
        );
        break;
      case 'render':
        members(o, '', { ...envelope, interactive: boolean });
        break;
      case 'set': {
        members(o, '', {
          ...envelope,
          camera: (v, at) => {
            members(v, at, cameraSpec(ranges));
            const camera = v as CameraPatch;
            if (camera.eye && camera.orbit) {
              reject('invalid_value', `${at}/orbit`, 'give eye or orbit, not both');
            }
            for (const other of ['orbit', 'eye', 'up'] as const) {
              if (camera.view && camera[other]) {
                reject('invalid_value', `${at}/view`, `give either view or ${other}, not both`);
              }
            }
            if (
              camera.eye &&
              camera.target &&
              subtract(camera.eye, camera.target).every((c) => c === 0)
            ) {
              reject('invalid_value', at, 'eye equals target');
            }
          },
          light: (v, at) => {
            members(v, at, lightSpec(ranges));
            const direction = (v as Partial<Light>).direction;
            if (direction && direction.every((c) => c === 0)) {
              reject('invalid_value', `${at}/direction`, 'zero direction');
            }
          },
          transfer_function: checkTransferFunction(ranges, limits, presets),
          settings: (v, at) => members(v, at, settingsSpec(limits, modes, ranges)),
          cut: (v, at) => members(v, at, cutSpec(ranges)),
          // Whether the session draws a label map, and holds each id, is the server's to say.
          labels: (v, at) => members(v, at, labelsSpec()),
          output: (v, at) =>
            members(v, at, {
              encoding: oneOf(ENCODINGS),
              jpeg_quality: ranged(ranges, 'output/jpeg_quality'),
              h264_quality: ranged(ranges, 'output/h264_quality'),
            }),
        });
        break;
      }
      default:
        reject('unknown_type', '/type', `unknown type "${String(o['type'])}"`);
    }
    return null;
  } catch (e) {
    if (e instanceof Reject) {
      return e.problem;
    }
    throw e;
  }
}
