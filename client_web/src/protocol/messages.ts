// Types for the Penumbra WebSocket protocol v1 (proto/README.md, proto/v1/*.schema.json) and the
// reading of server messages, each checked for the members this client reads (unknown members are
// ignored, as §3 asks). What a state holds, and each setting's kind, are the server's table
// (generated/server_tables.ts); the server checks what a client sends. No DOM here.

import {
  DEFAULT_LIMITS as SERVER_DEFAULT_LIMITS,
  ERROR_CODES,
  GRADIENTS,
  LISTINGS,
  POSITION_SPACES,
  SCATTERING_KINDS,
  SETTINGS,
  SHADOW_KINDS,
  TECHNIQUES,
  VIEWS,
  type StateSettings,
  type Vec3,
} from './generated/server_tables';
import {
  ProtocolError,
  UnknownMessageType,
  bool,
  isObject,
  need,
  num,
  numbers,
  obj,
  oneOf,
  optionalId,
  str,
} from './checks';

export { ProtocolError, UnknownMessageType } from './checks';

// The server's names and views, written from its tables into generated/ (scripts/update-schema.sh).
export {
  BUILDERS,
  COMPOSITINGS,
  DEFAULT_OUTPUT,
  DEFAULT_SETTINGS,
  ENCODINGS,
  ERROR_CODES,
  LIGHT_LOOKUPS,
  LIGHT_TYPES,
  LISTINGS,
  POSITION_SPACES,
  RECONSTRUCTIONS,
  SETTINGS,
  STAGES,
  VIEWS,
  type Size,
  type Vec3,
} from './generated/server_tables';

export const PROTOCOL_VERSION = 1;

export type Rgb = Vec3;

/** A camera, a light, the settings and the output as a state holds them (the server's table). */
export type Camera = StateSettings['camera'];
export type Light = StateSettings['light'];
export type Settings = StateSettings['settings'];
export type Output = StateSettings['output'];
export type Cut = StateSettings['cut'];

/** A mode's name; the server's `hello` lists the modes it offers (ModeCapabilities). */
export type Mode = Settings['mode'];
export type Encoding = Output['encoding'];
export type Compositing = Settings['compositing'];
export type Reconstruction = Settings['reconstruction'];
export type Stage = Settings['stage'];
export type Builder = Settings['light_buffer']['builder'];
export type LightLookup = Settings['light_buffer']['lookup'];
export type LightType = Light['type'];
/** Where positions lie: fractions of the volume's range, or Hounsfield units (the CT presets). */
export type PositionSpace = (typeof POSITION_SPACES)[number];
/** The space of the CT presets' positions, read as Hounsfield units. */
export const HOUNSFIELD: PositionSpace = 'hounsfield';
/** The space of a transfer function that names none. */
export const NORMALIZED: PositionSpace = 'normalized';
/** A transfer-function preset's name; the server's `hello` lists its presets with their points. */
export type Preset = string;
export type ViewName = (typeof VIEWS)[number];

export interface ColorPoint {
  x: number;
  rgb: Rgb;
}

export interface OpacityPoint {
  x: number;
  alpha: number;
}

export interface TransferFunctionPoints {
  name: string;
  space: PositionSpace;
  colors: ColorPoint[];
  opacities: OpacityPoint[];
}

export type TransferFunctionPatch =
  | { preset: Preset }
  | {
      name?: string;
      space?: PositionSpace;
      colors?: ColorPoint[];
      opacities?: OpacityPoint[];
    };

/** A session's full state as `opened`/`joined`/`state` report it; sending it back restores it. */
export interface State extends StateSettings {
  transfer_function: TransferFunctionPoints;
}

type DeepPartial<T> = {
  [K in keyof T]?: T[K] extends unknown[] ? T[K] : T[K] extends object ? DeepPartial<T[K]> : T[K];
};

/** The members of a `set`: every part and member optional; the transfer function replaces. */
export interface StatePatch {
  camera?: Partial<Camera>;
  light?: Partial<Light>;
  transfer_function?: TransferFunctionPatch;
  settings?: DeepPartial<Settings>;
  cut?: DeepPartial<Cut>;
  output?: Partial<Output>;
}

export interface VolumeSummary {
  id: string;
  name: string;
  dims: [number, number, number];
  spacing: Vec3;
  voxel_type: 'uint8' | 'uint16' | 'float32' | '';
  range: [number, number];
  /** The values are Hounsfield units: the CT presets (in HU) suit it. */
  hounsfield: boolean;
  loaded: boolean;
  /** Once loaded: the box in patient space (RAS mm) holding the voxels, [min, max] corner. */
  bounds?: [Vec3, Vec3];
}

/** The limits a server is configured with (`penumbra serve` options), named as hello.limits does. */
export type ConfiguredLimits = { -readonly [K in keyof typeof SERVER_DEFAULT_LIMITS]: number };

/**
 * What a server accepts (hello.limits): its configured limits, and those the protocol fixes: the
 * points of a transfer function's list, how far a Hounsfield position reaches, and the longest
 * string each string member of a request takes, keyed `type/member` (`open/volume`,
 * `set/transfer_function/name`).
 */
export interface Limits extends ConfiguredLimits {
  max_transfer_function_points: number;
  max_hounsfield_position: number;
  max_string_bytes: Record<string, number>;
}

/** A server's configured limits at their defaults: what the controls span until its hello. */
export const DEFAULT_LIMITS: ConfiguredLimits = SERVER_DEFAULT_LIMITS;

export type ErrorCode = (typeof ERROR_CODES)[number];

/**
 * The codes the server's scheduler sends in a render's place (its frame sink in
 * connection_handler.cpp). The scheduler answers renders in order, coalescing, so such an error
 * for render r, like a frame for r, also answers every older render still outstanding. Any other
 * code carrying a render's id (`rate_limited`, a message the parser refused, `no_session`) is sent
 * the moment the render arrives, while the older ones are still queued: it answers that render only.
 */
const ANSWERED_IN_ORDER: readonly ErrorCode[] = ['too_much_work', 'render_failed'];

/** Whether an error with this code for render r answers the older outstanding renders too. */
export function answersOlderRenders(code: string): boolean {
  return (ANSWERED_IN_ORDER as readonly string[]).includes(code);
}

// ---- server to client ---------------------------------------------------------------------------

/** What a mode computes, from the server's mode table: which parameters it reads. */
export interface ModeCapabilities {
  name: Mode;
  summary: string;
  technique: (typeof TECHNIQUES)[number];
  shadows: (typeof SHADOW_KINDS)[number];
  scattering: (typeof SCATTERING_KINDS)[number];
  gradients: (typeof GRADIENTS)[number];
}

/** One setting's range from the server's table, both ends included. */
export interface SettingRange {
  min: number;
  max: number;
  integer: boolean;
  /** What the setting does, where the server says (the panel shows it as the control's hint). */
  summary?: string;
}

/**
 * Each setting's range (hello.ranges), keyed by its path in a `set` patch
 * (`settings/light_buffer/compensation`, `camera/fov`), with `vec3` for each coordinate and `rgb`
 * for each colour channel. The client holds no ranges of its own.
 */
export type SettingRanges = Record<string, SettingRange>;

export interface HelloMessage {
  v: 1;
  type: 'hello';
  server: string;
  modes: ModeCapabilities[];
  ranges: SettingRanges;
  /** The transfer-function presets, each as a state holds it once `{preset: name}` set it. */
  presets: TransferFunctionPoints[];
  /** [min, max] HU over which Hounsfield positions are read on a volume not marked HU. */
  nominal_ct_range: [number, number];
  encodings: Encoding[];
  renderer: { renderer: string; version: string; platform: string; software: boolean };
  limits: Limits;
}

/** Where the server's listing of its data folder stands: `scanning` while its first scan runs. */
export type Listing = (typeof LISTINGS)[number];

export interface VolumesMessage {
  v: 1;
  type: 'volumes';
  id?: number;
  volumes: VolumeSummary[];
  listing: Listing;
}

export interface OpenedMessage {
  v: 1;
  type: 'opened' | 'joined';
  id?: number;
  session: string;
  volume: VolumeSummary;
  histogram: number[];
  state: State;
  /** `opened` only: the secret that `resume` takes to make a new connection the owner again. */
  owner_token?: string;
  /**
   * `opened` for a resume only: the server that held the session is gone and this one re-created
   * it under its id with the default state; the owner sends its state back.
   */
  recreated?: true;
}

/** The session's full state after its owner changed it; viewers get it, the owner its `set`'s ack. */
export interface StateMessage {
  v: 1;
  type: 'state';
  session: string;
  state: State;
}

export interface AckMessage {
  v: 1;
  type: 'ack';
  id?: number;
  of: string;
  /** Answering a `set`: the session's state as the server made it of the patch. */
  state?: State;
}

export interface StatsMessage {
  v: 1;
  type: 'stats';
  id?: number;
  stats: Record<string, unknown>;
}

export interface ErrorMessage {
  v: 1;
  type: 'error';
  id?: number;
  code: ErrorCode | string;
  message: string;
  field: string;
}

export type ServerMessage =
  | HelloMessage
  | VolumesMessage
  | OpenedMessage
  | StateMessage
  | AckMessage
  | StatsMessage
  | ErrorMessage;

// ---- client to server ---------------------------------------------------------------------------

export type ClientMessage =
  | { v: 1; type: 'list_volumes'; id?: number }
  | { v: 1; type: 'open'; id?: number; volume: string }
  | { v: 1; type: 'join'; id?: number; session: string }
  | ({ v: 1; type: 'set'; id?: number } & StatePatch)
  | { v: 1; type: 'render'; id?: number; interactive?: boolean }
  | { v: 1; type: 'stats'; id?: number }
  | { v: 1; type: 'close'; id?: number }
  | { v: 1; type: 'resume'; id?: number; session: string; owner_token: string; volume?: string };

export type ClientMessageType = ClientMessage['type'];

/**
 * The message types that answer each request (proto/README.md §4) besides `error`; `render` is
 * answered by a binary frame. A request type missing here does not compile.
 */
export const ANSWERS = {
  list_volumes: ['volumes'],
  open: ['opened'],
  join: ['joined'],
  set: ['ack'],
  render: [],
  stats: ['stats'],
  close: ['ack'],
  resume: ['opened'],
} as const satisfies Record<ClientMessageType, readonly ServerMessage['type'][]>;

/** The message that answers a request of type `T`. */
export type AnswerTo<T extends ClientMessageType> = ServerMessage extends infer M
  ? M extends ServerMessage
    ? [M['type'] & (typeof ANSWERS)[T][number]] extends [never]
      ? never
      : M
    : never
  : never;

/** A request as a caller gives it: the connection adds `v` and `id`. */
export type ClientRequest = ClientMessage extends infer M
  ? M extends ClientMessage
    ? Omit<M, 'v' | 'id'>
    : never
  : never;

function checkVolumeSummary(v: unknown, at: string): VolumeSummary {
  const o = need(isObject(v), v as Record<string, unknown>, 'a volume summary', at);
  str(o, 'id', at);
  str(o, 'name', at);
  numbers(o, 'dims', at, 3);
  numbers(o, 'spacing', at, 3);
  str(o, 'voxel_type', at);
  numbers(o, 'range', at, 2);
  bool(o, 'hounsfield', at);
  bool(o, 'loaded', at);
  if (o['bounds'] !== undefined) {
    const bounds = need(
      Array.isArray(o['bounds']),
      o['bounds'] as unknown[],
      'two corners',
      `${at}/bounds`,
    );
    need(bounds.length === 2, null, 'two corners', `${at}/bounds`);
    numbers(bounds as unknown as Record<string, unknown>, '0', `${at}/bounds`, 3);
    numbers(bounds as unknown as Record<string, unknown>, '1', `${at}/bounds`, 3);
  }
  return o as unknown as VolumeSummary;
}

/** A transfer function's colour and opacity points (a state's, a preset's). */
function checkPoints(tf: Record<string, unknown>, tfAt: string): void {
  need(Array.isArray(tf['colors']), null, 'an array', `${tfAt}/colors`);
  need(Array.isArray(tf['opacities']), null, 'an array', `${tfAt}/opacities`);
  (tf['colors'] as unknown[]).forEach((p, i) => {
    const point = need(isObject(p), p as Record<string, unknown>, 'a point', `${tfAt}/colors/${i}`);
    num(point, 'x', `${tfAt}/colors/${i}`);
    numbers(point, 'rgb', `${tfAt}/colors/${i}`, 3);
  });
  (tf['opacities'] as unknown[]).forEach((p, i) => {
    const point = need(
      isObject(p),
      p as Record<string, unknown>,
      'a point',
      `${tfAt}/opacities/${i}`,
    );
    num(point, 'x', `${tfAt}/opacities/${i}`);
    num(point, 'alpha', `${tfAt}/opacities/${i}`);
  });
}

/** A setting of a state, as the server's table says it is: a number, a whole one, a boolean, a
 * name, three numbers or two. A choice is read as text: a newer server may offer more names. */
function checkSetting(o: Record<string, unknown>, key: string, at: string, kind: string): void {
  switch (kind) {
    case 'number':
      num(o, key, at);
      break;
    case 'integer':
      need(Number.isInteger(num(o, key, at)), null, 'an integer', `${at}/${key}`);
      break;
    case 'boolean':
      bool(o, key, at);
      break;
    case 'choice':
      str(o, key, at);
      break;
    case 'vector':
      numbers(o, key, at, 3);
      break;
    default:
      numbers(o, key, at, 2);
  }
}

function checkState(v: unknown, at: string): State {
  const o = need(isObject(v), v as Record<string, unknown>, 'a state', at);
  for (const [path, setting] of Object.entries(SETTINGS)) {
    const parts = path.split('/');
    const name = parts.pop()!;
    let parent = o;
    let parentAt = at;
    for (const part of parts) {
      parent = obj(parent, part, parentAt);
      parentAt += `/${part}`;
    }
    checkSetting(parent, name, parentAt, setting.kind);
  }
  checkPoints(obj(o, 'transfer_function', at), `${at}/transfer_function`);
  return o as unknown as State;
}

/**
 * Parses one text message from the server. Throws ProtocolError when it is not JSON, not v1, or
 * lacks a member this client reads, and UnknownMessageType (a ProtocolError) for a type it does not
 * know; members it does not know are kept and ignored.
 */
export function parseServerMessage(text: string): ServerMessage {
  let value: unknown;
  try {
    value = JSON.parse(text);
  } catch {
    throw new ProtocolError('not JSON', '/');
  }
  const o = need(isObject(value), value as Record<string, unknown>, 'a JSON object', '/');
  need(o['v'] === PROTOCOL_VERSION, null, 'v: 1', '/v');
  const type = str(o, 'type', '');
  optionalId(o);
  switch (type) {
    case 'hello': {
      str(o, 'server', '');
      need(Array.isArray(o['modes']), null, 'an array of modes', '/modes');
      const modes = o['modes'] as Record<string, unknown>;
      (o['modes'] as unknown[]).forEach((_, i) => {
        const mode = obj(modes, String(i), '/modes');
        for (const key of ['name', 'summary', 'technique', 'shadows', 'scattering', 'gradients']) {
          str(mode, key, `/modes/${i}`);
        }
      });
      const ranges = obj(o, 'ranges', '');
      for (const path of Object.keys(ranges)) {
        const range = obj(ranges, path, '/ranges');
        num(range, 'min', `/ranges/${path}`);
        num(range, 'max', `/ranges/${path}`);
        bool(range, 'integer', `/ranges/${path}`);
        if (range['summary'] !== undefined) str(range, 'summary', `/ranges/${path}`);
      }
      need(Array.isArray(o['presets']), null, 'an array of presets', '/presets');
      (o['presets'] as unknown[]).forEach((p, i) => {
        const preset = need(isObject(p), p as Record<string, unknown>, 'a preset', `/presets/${i}`);
        str(preset, 'name', `/presets/${i}`);
        str(preset, 'space', `/presets/${i}`);
        checkPoints(preset, `/presets/${i}`);
      });
      numbers(o, 'nominal_ct_range', '', 2);
      need(Array.isArray(o['encodings']), null, 'an array of encodings', '/encodings');
      const renderer = obj(o, 'renderer', '');
      for (const key of ['renderer', 'version', 'platform']) {
        str(renderer, key, '/renderer');
      }
      bool(renderer, 'software', '/renderer');
      const limits = obj(o, 'limits', '');
      // Every number a server's hello.limits has (the generated defaults name them).
      for (const key of Object.keys(SERVER_DEFAULT_LIMITS)) {
        num(limits, key, '/limits');
      }
      const lengths = obj(limits, 'max_string_bytes', '/limits');
      for (const key of Object.keys(lengths)) num(lengths, key, '/limits/max_string_bytes');
      return o as unknown as HelloMessage;
    }
    case 'volumes': {
      need(Array.isArray(o['volumes']), null, 'an array', '/volumes');
      (o['volumes'] as unknown[]).forEach((v, i) => checkVolumeSummary(v, `/volumes/${i}`));
      oneOf(o['listing'], LISTINGS, '/listing');
      return o as unknown as VolumesMessage;
    }
    case 'opened':
    case 'joined': {
      str(o, 'session', '');
      checkVolumeSummary(o['volume'], '/volume');
      numbers(o, 'histogram', '');
      checkState(o['state'], '/state');
      // A server older than resume sends no token; its owner then cannot resume.
      if (o['owner_token'] !== undefined) str(o, 'owner_token', '');
      need(
        o['recreated'] === undefined || o['recreated'] === true,
        o['recreated'],
        'true',
        '/recreated',
      );
      return o as unknown as OpenedMessage;
    }
    case 'state':
      str(o, 'session', '');
      checkState(o['state'], '/state');
      return o as unknown as StateMessage;
    case 'ack':
      str(o, 'of', '');
      if (o['state'] !== undefined) checkState(o['state'], '/state');
      return o as unknown as AckMessage;
    case 'stats':
      obj(o, 'stats', '');
      return o as unknown as StatsMessage;
    case 'error':
      str(o, 'code', '');
      str(o, 'message', '');
      str(o, 'field', '');
      return o as unknown as ErrorMessage;
    default:
      throw new UnknownMessageType(type);
  }
}

/** The text of a client message. */
export function encodeClientMessage(message: ClientMessage): string {
  return JSON.stringify(message);
}

// ---- patches --------------------------------------------------------------------------------------

function merged(a: unknown, b: unknown): unknown {
  if (!isObject(a) || !isObject(b)) return b;
  const out: Record<string, unknown> = { ...a };
  for (const [key, value] of Object.entries(b)) out[key] = merged(a[key], value);
  return out;
}

/**
 * Two patches as one, the later winning member by member; a list (a vector, a size) and the
 * transfer function replace whole. What the server makes of the result is its own: the client
 * shows the state a `set` is answered with.
 */
export function mergePatches(a: StatePatch, b: StatePatch): StatePatch {
  const out = structuredClone(a) as Record<string, unknown>;
  for (const [key, value] of Object.entries(structuredClone(b))) {
    out[key] = key === 'transfer_function' ? value : merged(out[key], value);
  }
  return out as StatePatch;
}

/** A `set` patch that restores `state` whole (what a reconnecting owner sends). */
export function restorePatch(state: State): StatePatch {
  return structuredClone(state);
}
