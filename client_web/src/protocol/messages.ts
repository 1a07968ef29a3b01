// Types for the Penumbra WebSocket protocol v1 (proto/README.md, proto/v1/*.schema.json) and the
// checks a client needs: server messages are checked for the members this client reads (unknown
// members are ignored, as §3 asks), client messages are checked as strictly as the server does, so
// the tests can hold them against proto/examples/v1. No DOM here.

import {
  BUILDERS,
  COMPOSITINGS,
  DEFAULT_CAMERA_DISTANCE,
  DEFAULT_LIMITS as SERVER_DEFAULT_LIMITS,
  DEFAULT_OUTPUT,
  DEFAULT_POSITION_SPACE,
  DEFAULT_SETTINGS,
  ENCODINGS,
  GRADIENTS,
  LIGHT_LOOKUPS,
  LIGHT_TYPES,
  MAX_ORBIT_ELEVATION,
  POSITION_SPACES,
  SCATTERING_KINDS,
  SHADOW_KINDS,
  STAGES,
  TECHNIQUES,
  UNNAMED_TRANSFER_FUNCTION,
  VIEW_POSES,
  VIEWS,
} from './generated/server_tables';

// The server's names and views, written from its tables into generated/ (scripts/update-schema.sh).
export {
  BUILDERS,
  COMPOSITINGS,
  DEFAULT_OUTPUT,
  DEFAULT_SETTINGS,
  ENCODINGS,
  LIGHT_LOOKUPS,
  LIGHT_TYPES,
  POSITION_SPACES,
  STAGES,
  VIEWS,
};

export const PROTOCOL_VERSION = 1;

export type Vec3 = [number, number, number];
export type Rgb = [number, number, number];

/** A mode's name; the server's `hello` lists the modes it offers (ModeCapabilities). */
export type Mode = string;
export type Encoding = (typeof ENCODINGS)[number];
/** Where positions lie: fractions of the volume's range, or Hounsfield units (the CT presets). */
export type PositionSpace = (typeof POSITION_SPACES)[number];
/** The space of the CT presets' positions, read as Hounsfield units. */
export const HOUNSFIELD: PositionSpace = 'hounsfield';
/** The space of a transfer function that names none. */
export const NORMALIZED: PositionSpace = 'normalized';
/** A transfer-function preset's name; the server's `hello` lists its presets with their points. */
export type Preset = string;
export type Compositing = (typeof COMPOSITINGS)[number];
export type Stage = (typeof STAGES)[number];
export type Builder = (typeof BUILDERS)[number];
export type LightLookup = (typeof LIGHT_LOOKUPS)[number];
export type ViewName = (typeof VIEWS)[number];

/** The eye and up of `view` looking at `target` from `distance`, as the server poses them. */
export function viewPose(view: ViewName, target: Vec3, distance: number): { eye: Vec3; up: Vec3 } {
  const { side, up } = VIEW_POSES[view];
  return {
    eye: [
      target[0] + distance * side[0],
      target[1] + distance * side[1],
      target[2] + distance * side[2],
    ],
    up: [...up],
  };
}
export type LightType = (typeof LIGHT_TYPES)[number];

export interface Camera {
  eye: Vec3;
  target: Vec3;
  up: Vec3;
  fov: number;
}

export interface Orbit {
  azimuth?: number;
  elevation?: number;
  distance?: number;
}

export interface CameraPatch {
  eye?: Vec3;
  target?: Vec3;
  up?: Vec3;
  fov?: number;
  orbit?: Orbit;
  view?: ViewName;
}

export interface Light {
  type: LightType;
  direction: Vec3;
  position: Vec3;
  color: Rgb;
  intensity: number;
  ambient: number;
}

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

export interface Shading {
  diffuse: number;
  specular: number;
  shininess: number;
}

export interface LightBufferSettings {
  slices: number;
  resolution: number;
  builder: Builder;
  compensation: number;
  slab_samples: number;
  lookup: LightLookup;
}

export interface Scattering {
  shell_radius: number;
  shell_rings: number;
  shell_center_weight: number;
  cone_angle: number;
  cone_center_weight: number;
}

export interface Settings {
  mode: Mode;
  compositing: Compositing;
  stage: Stage;
  size: [number, number];
  sample_distance: number;
  opacity_unit_distance: number;
  early_termination: number;
  background: Rgb;
  phong: boolean;
  shading: Shading;
  light_buffer: LightBufferSettings;
  scattering: Scattering;
  /** > 0: the server picks mode and quality so a frame fits this many ms; 0: as set. Newer servers. */
  frame_budget_ms?: number;
  /** Ray-cast modes: per-pixel jittered sample offsets instead of the step's midpoint. Newer servers. */
  jitter?: boolean;
  /** Refinement steps after a still frame of a jittered ray-cast mode; 0 turns it off. Newer servers. */
  refinement_steps?: number;
  /** Skip the volume's empty bricks while marching (the image stays the same). Newer servers. */
  empty_space_skipping?: boolean;
}

export interface Output {
  encoding: Encoding;
  jpeg_quality: number;
}

/** A session's full state as `opened`/`joined` report it; sending it back restores it. */
export interface State {
  camera: Camera;
  light: Light;
  transfer_function: TransferFunctionPoints;
  settings: Settings;
  output: Output;
}

type DeepPartial<T> = {
  [K in keyof T]?: T[K] extends unknown[] ? T[K] : T[K] extends object ? DeepPartial<T[K]> : T[K];
};

/** The members of a `set`: every part and member optional; the transfer function replaces. */
export interface StatePatch {
  camera?: CameraPatch;
  light?: Partial<Light>;
  transfer_function?: TransferFunctionPatch;
  settings?: DeepPartial<Settings>;
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
}

/** The limits a server is configured with (`penumbra serve` options). */
export interface ConfiguredLimits {
  max_message_bytes: number;
  max_image_side: number;
  max_slices: number;
  max_light_resolution: number;
  max_sessions: number;
  max_sessions_per_client: number;
  max_sessions_per_connection: number;
  max_requests_per_second: number;
  max_send_queue: number;
  max_frame_work: number;
  max_json_depth: number;
}

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

export const ERROR_CODES = [
  'malformed_json',
  'invalid_message',
  'unknown_type',
  'unknown_field',
  'unsupported_version',
  'invalid_value',
  'out_of_range',
  'message_too_large',
  'rate_limited',
  'unknown_volume',
  'volume_unreadable',
  'unknown_session',
  'no_session',
  'too_many_sessions',
  'session_owned',
  'render_failed',
  'too_much_work',
  'internal_error',
] as const;
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

export interface VolumesMessage {
  v: 1;
  type: 'volumes';
  id?: number;
  volumes: VolumeSummary[];
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

/** The session's full state after its owner changed it; viewers get it, the owner does not. */
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

/** Thrown when a server message does not have the shape protocol v1 promises. */
export class ProtocolError extends Error {
  constructor(
    message: string,
    readonly field: string,
  ) {
    super(`${message} (at ${field || '/'})`);
    this.name = 'ProtocolError';
  }
}

/**
 * Thrown for a message type this client does not know. Within v1 the server may add message types
 * that answer no request (§3), so a client ignores them rather than report a problem.
 */
export class UnknownMessageType extends ProtocolError {
  constructor(readonly type: string) {
    super(`unknown message type "${type}"`, '/type');
    this.name = 'UnknownMessageType';
  }
}

// ---- small checkers -----------------------------------------------------------------------------

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

function need<T>(ok: boolean, value: T, what: string, field: string): T {
  if (!ok) {
    throw new ProtocolError(`expected ${what}`, field);
  }
  return value;
}

function str(o: Record<string, unknown>, key: string, at: string): string {
  const v = o[key];
  return need(typeof v === 'string', v as string, 'a string', `${at}/${key}`);
}

function num(o: Record<string, unknown>, key: string, at: string): number {
  const v = o[key];
  return need(typeof v === 'number' && Number.isFinite(v), v as number, 'a number', `${at}/${key}`);
}

function bool(o: Record<string, unknown>, key: string, at: string): boolean {
  const v = o[key];
  return need(typeof v === 'boolean', v as boolean, 'a boolean', `${at}/${key}`);
}

function obj(o: Record<string, unknown>, key: string, at: string): Record<string, unknown> {
  const v = o[key];
  return need(isObject(v), v as Record<string, unknown>, 'an object', `${at}/${key}`);
}

function numbers(o: Record<string, unknown>, key: string, at: string, length?: number): number[] {
  const v = o[key];
  const ok =
    Array.isArray(v) &&
    (length === undefined || v.length === length) &&
    v.every((x) => typeof x === 'number' && Number.isFinite(x));
  return need(ok, v as number[], length ? `${length} numbers` : 'numbers', `${at}/${key}`);
}

function optionalId(o: Record<string, unknown>): number | undefined {
  if (o['id'] === undefined) {
    return undefined;
  }
  return need(Number.isInteger(o['id']), o['id'] as number, 'an integer', '/id');
}

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
  return o as unknown as VolumeSummary;
}

/**
 * Settings the server announces a range for that a state may lack: servers older than them leave
 * them out. Every other announced setting whose part the state has is required in it.
 */
const NOT_IN_EVERY_STATE = new Set(['settings/frame_budget_ms', 'settings/refinement_steps']);

/**
 * The numbers of a state that hello.ranges announces (`settings/light_buffer/compensation`): each
 * a finite number, a whole one where the range says so. Paths whose part a state does not hold
 * (`camera/orbit/azimuth`, and `vec3`, `rgb`, which are no members) are left out.
 */
function checkRangedNumbers(
  state: Record<string, unknown>,
  ranges: SettingRanges,
  at: string,
): void {
  for (const [path, range] of Object.entries(ranges)) {
    const parts = path.split('/');
    const name = parts.pop()!;
    let parent: Record<string, unknown> | undefined = parts.length > 0 ? state : undefined;
    for (const part of parts) {
      const next: unknown = parent?.[part];
      parent = isObject(next) ? next : undefined;
    }
    if (parent === undefined || (!(name in parent) && NOT_IN_EVERY_STATE.has(path))) continue;
    const value = num(parent, name, `${at}/${parts.join('/')}`);
    need(!range.integer || Number.isInteger(value), value, 'an integer', `${at}/${path}`);
  }
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

function checkState(v: unknown, at: string, ranges: SettingRanges): State {
  const o = need(isObject(v), v as Record<string, unknown>, 'a state', at);
  const camera = obj(o, 'camera', at);
  for (const key of ['eye', 'target', 'up']) {
    numbers(camera, key, `${at}/camera`, 3);
  }
  const light = obj(o, 'light', at);
  str(light, 'type', `${at}/light`);
  numbers(light, 'direction', `${at}/light`, 3);
  numbers(light, 'position', `${at}/light`, 3);
  numbers(light, 'color', `${at}/light`, 3);
  checkPoints(obj(o, 'transfer_function', at), `${at}/transfer_function`);
  const settings = obj(o, 'settings', at);
  const sAt = `${at}/settings`;
  str(settings, 'mode', sAt);
  str(settings, 'compositing', sAt);
  str(settings, 'stage', sAt);
  numbers(settings, 'size', sAt, 2);
  numbers(settings, 'background', sAt, 3);
  bool(settings, 'phong', sAt);
  obj(settings, 'shading', sAt);
  obj(settings, 'scattering', sAt);
  const lb = obj(settings, 'light_buffer', sAt);
  // Bounded by the server's limits (hello.limits), not by a range.
  num(lb, 'slices', `${sAt}/light_buffer`);
  num(lb, 'resolution', `${sAt}/light_buffer`);
  str(lb, 'builder', `${sAt}/light_buffer`);
  str(lb, 'lookup', `${sAt}/light_buffer`);
  const output = obj(o, 'output', at);
  str(output, 'encoding', `${at}/output`);
  num(output, 'jpeg_quality', `${at}/output`);
  checkRangedNumbers(o, ranges, at);
  return o as unknown as State;
}

/**
 * Parses one text message from the server. Throws ProtocolError when it is not JSON, not v1, or
 * lacks a member this client reads, and UnknownMessageType (a ProtocolError) for a type it does not
 * know; members it does not know are kept and ignored. `ranges`: the server's (its hello), which
 * say what numbers a state holds; a state before them is refused.
 */
export function parseServerMessage(text: string, ranges?: SettingRanges): ServerMessage {
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
      return o as unknown as VolumesMessage;
    }
    case 'opened':
    case 'joined': {
      str(o, 'session', '');
      checkVolumeSummary(o['volume'], '/volume');
      numbers(o, 'histogram', '');
      checkState(o['state'], '/state', rangesForState(ranges));
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
      checkState(o['state'], '/state', rangesForState(ranges));
      return o as unknown as StateMessage;
    case 'ack':
      str(o, 'of', '');
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

function rangesForState(ranges: SettingRanges | undefined): SettingRanges {
  if (ranges === undefined) {
    throw new ProtocolError("a state before the server's hello (its ranges)", '/state');
  }
  return ranges;
}

/** The text of a client message. */
export function encodeClientMessage(message: ClientMessage): string {
  return JSON.stringify(message);
}

// ---- client message checks (as the server does them, at its hello's terms) ------------------

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
      stage: oneOf(STAGES),
      size: vector(2, integer(1, limits.max_image_side)),
      background: rgb(ranges),
      phong: boolean,
      empty_space_skipping: boolean,
      jitter: boolean,
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
          output: (v, at) =>
            members(v, at, {
              encoding: oneOf(ENCODINGS),
              jpeg_quality: ranged(ranges, 'output/jpeg_quality'),
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

// ---- state mirror -------------------------------------------------------------------------------

function deg(radians: number): number {
  return (radians * 180) / Math.PI;
}

/** The eye an `orbit` puts around `target` (§5): azimuth from +y toward +x about +z. */
export function orbitEye(target: Vec3, orbit: Orbit): Vec3 {
  const az = ((orbit.azimuth ?? 0) * Math.PI) / 180;
  const el =
    (Math.max(-MAX_ORBIT_ELEVATION, Math.min(MAX_ORBIT_ELEVATION, orbit.elevation ?? 0)) *
      Math.PI) /
    180;
  const d = orbit.distance ?? DEFAULT_CAMERA_DISTANCE;
  return [
    target[0] + d * Math.cos(el) * Math.sin(az),
    target[1] + d * Math.cos(el) * Math.cos(az),
    target[2] + d * Math.sin(el),
  ];
}

/** Azimuth, elevation (degrees) and distance of `eye` around `target`; the inverse of orbitEye. */
export function orbitOf(eye: Vec3, target: Vec3): Required<Orbit> {
  const [x, y, z] = subtract(eye, target);
  const distance = Math.hypot(x, y, z);
  return {
    azimuth: deg(Math.atan2(x, y)),
    elevation: distance > 0 ? deg(Math.asin(Math.max(-1, Math.min(1, z / distance)))) : 0,
    distance,
  };
}

/**
 * The state after the server accepted `patch` (its `ack`), so a reconnecting client can send it
 * back. A preset transfer function is kept as `presetPoints` gives it (the server's presets, from
 * its hello), or left as it was when that is not known.
 */
export function applyPatch(
  state: State,
  patch: StatePatch,
  presetPoints?: (preset: Preset) => TransferFunctionPoints | undefined,
): State {
  const next: State = structuredClone(state);
  if (patch.camera) {
    const { orbit, view, ...rest } = patch.camera;
    // A view keeps the camera's distance from its target.
    const distance = Math.hypot(...subtract(state.camera.eye, state.camera.target));
    Object.assign(next.camera, structuredClone(rest));
    if (orbit) {
      next.camera.eye = orbitEye(next.camera.target, orbit);
      next.camera.up = [0, 0, 1];
    }
    if (view) {
      Object.assign(
        next.camera,
        viewPose(view, next.camera.target, distance > 0 ? distance : DEFAULT_CAMERA_DISTANCE),
      );
    }
  }
  if (patch.light) {
    Object.assign(next.light, structuredClone(patch.light));
  }
  if (patch.transfer_function) {
    const tf = patch.transfer_function;
    if ('preset' in tf) {
      const points = presetPoints?.(tf.preset);
      if (points) {
        next.transfer_function = structuredClone(points);
      }
    } else {
      next.transfer_function = {
        name: tf.name ?? UNNAMED_TRANSFER_FUNCTION,
        space: tf.space ?? DEFAULT_POSITION_SPACE,
        colors: structuredClone(tf.colors ?? []),
        opacities: structuredClone(tf.opacities ?? []),
      };
    }
  }
  if (patch.settings) {
    // A part (light_buffer, shading, ...) takes the patch's members and keeps the others.
    const settings = next.settings as unknown as Record<string, unknown>;
    for (const [key, value] of Object.entries(structuredClone(patch.settings))) {
      const prev = settings[key];
      settings[key] = isObject(prev) && isObject(value) ? { ...prev, ...value } : value;
    }
  }
  if (patch.output) {
    Object.assign(next.output, patch.output);
  }
  return next;
}

/** Merges two patches, the later winning member by member (a transfer function replaces). */
export function mergePatches(a: StatePatch, b: StatePatch): StatePatch {
  const out: StatePatch = structuredClone(a);
  if (b.camera) {
    const camera: CameraPatch = { ...(out.camera ?? {}), ...structuredClone(b.camera) };
    if (b.camera.eye) delete camera.orbit;
    if (b.camera.orbit) delete camera.eye;
    if (b.camera.eye || b.camera.orbit || b.camera.up) delete camera.view;
    if (b.camera.view) {
      delete camera.eye;
      delete camera.orbit;
      delete camera.up;
    }
    out.camera = camera;
  }
  if (b.light) out.light = { ...(out.light ?? {}), ...structuredClone(b.light) };
  if (b.transfer_function) out.transfer_function = structuredClone(b.transfer_function);
  if (b.settings) {
    const s = { ...(out.settings ?? {}) };
    for (const [key, value] of Object.entries(structuredClone(b.settings))) {
      const prev = (s as Record<string, unknown>)[key];
      (s as Record<string, unknown>)[key] =
        isObject(prev) && isObject(value) ? { ...prev, ...value } : value;
    }
    out.settings = s;
  }
  if (b.output) out.output = { ...(out.output ?? {}), ...b.output };
  return out;
}

/** A `set` patch that restores `state` whole (what a reconnecting owner sends). */
export function restorePatch(state: State): StatePatch {
  return structuredClone(state);
}
