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

/** How one label of a label map is drawn: its colour (channels 0..1), opacity and visibility. */
export interface LabelStyle {
  color: Rgb;
  /** Scales the opacity the transfer function gives the label's samples. */
  opacity: number;
  /** A hidden label is transparent to the camera and to the light. */
  visible: boolean;
}

/** A state's labels, present only while the session draws a label map (`add_labels`). */
export interface LabelsState {
  /** How much a label's colour replaces the transfer function's, 0..1. */
  blend: number;
  /**
   * The label map drawn alone, without the scan: each visible label a smooth lit surface in its
   * colour (the transfer function and the blend set aside). Absent from an older server: false.
   */
  alone?: boolean;
  /** Every label's style, keyed by its id written as text. */
  styles: Record<string, LabelStyle>;
}

/**
 * A `set`'s labels, which the server applies in the order all, only, styles, blend, alone; refused
 * while the session draws no label map.
 */
export interface LabelsPatch {
  all?: { opacity?: number; visible?: boolean };
  /** These ids visible, every other label hidden. */
  only?: number[];
  styles?: Record<string, Partial<LabelStyle>>;
  blend?: number;
  alone?: boolean;
}

/** A session's full state as `opened`/`joined`/`state` report it; sending it back restores it. */
export interface State extends StateSettings {
  transfer_function: TransferFunctionPoints;
  labels?: LabelsState;
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
  labels?: LabelsPatch;
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
  /**
   * The server would draw it as a label map (`add_labels`): a NIfTI with the label intent or
   * MRIcron's names beside it, a Slicer .seg.nrrd. Absent from servers older than label maps.
   */
  label_map?: boolean;
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

/** One label of a label map as `labels` lists it. */
export interface LabelSummary {
  id: number;
  name: string;
  /** As its files give it, 0..255 a channel. */
  color: [number, number, number];
  voxels: number;
}

/**
 * The label map a session draws (`volume`, "" for none) and its labels, with the state their
 * styles are now in: answers add_labels and remove_labels, and follows `joined` (and a resume's
 * `opened`) without an id when the session draws one.
 */
export interface LabelsMessage {
  v: 1;
  type: 'labels';
  id?: number;
  session: string;
  volume: string;
  labels: LabelSummary[];
  state: State;
}

/** What lies under a point of the view (`pick`); without a hit, only x, y and hit. */
export interface PickedMessage {
  v: 1;
  type: 'picked';
  id?: number;
  session: string;
  x: number;
  y: number;
  hit: boolean;
  /** Where the eye sees a surface through the point, patient RAS millimetres. */
  position?: Vec3;
  /** The scan's value there, in its real units. */
  value?: number;
  hounsfield?: boolean;
  /** The label drawn there; absent for none. */
  label?: { id: number; name: string };
}

/** Where an export stands (`export`, `export_movie`): at once, after each tile, and when it ends. */
export interface ExportStatusMessage {
  v: 1;
  type: 'export_status';
  id?: number;
  /** The export's id, the right to download it. */
  export: string;
  state: 'running' | 'done' | 'failed' | 'cancelled';
  progress: number;
  width: number;
  height: number;
  tiles: number;
  /** A movie's frames. */
  frames?: number;
  /** Done: the path to GET the PNG (or the MP4) from on the server. */
  url?: string;
  bytes?: number;
  /** Failed: why. */
  error?: { code: ErrorCode | string; message: string };
}

export const EXPORT_STATES: readonly ExportStatusMessage['state'][] = [
  'running',
  'done',
  'failed',
  'cancelled',
];

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
  | LabelsMessage
  | PickedMessage
  | ExportStatusMessage
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
  | { v: 1; type: 'resume'; id?: number; session: string; owner_token: string; volume?: string }
  | { v: 1; type: 'add_labels'; id?: number; volume: string }
  | { v: 1; type: 'remove_labels'; id?: number }
  | { v: 1; type: 'pick'; id?: number; x: number; y: number }
  | { v: 1; type: 'export'; id?: number; width: number; height: number }
  | {
      v: 1;
      type: 'export_movie';
      id?: number;
      width: number;
      height: number;
      frames: number;
      rock: number;
    }
  | { v: 1; type: 'cancel_export'; id?: number; export: string };

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
  add_labels: ['labels'],
  remove_labels: ['labels'],
  pick: ['picked'],
  // The first status; the rest come as the connection's `exportStatus` events.
  export: ['export_status'],
  export_movie: ['export_status'],
  // Answered by the export's own status, `cancelled`.
  cancel_export: [],
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
  if (o['label_map'] !== undefined) bool(o, 'label_map', at);
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
  if (o['labels'] !== undefined) checkLabelsState(o['labels'], `${at}/labels`);
  return o as unknown as State;
}

function checkLabelsState(v: unknown, at: string): void {
  const o = need(isObject(v), v as Record<string, unknown>, 'an object', at);
  num(o, 'blend', at);
  if (o['alone'] !== undefined) bool(o, 'alone', at);
  const styles = obj(o, 'styles', at);
  for (const [id, style] of Object.entries(styles)) {
    need(/^-?[0-9]+$/.test(id), null, 'label ids as keys', `${at}/styles`);
    const s = need(
      isObject(style),
      style as Record<string, unknown>,
      'a style',
      `${at}/styles/${id}`,
    );
    numbers(s, 'color', `${at}/styles/${id}`, 3);
    num(s, 'opacity', `${at}/styles/${id}`);
    bool(s, 'visible', `${at}/styles/${id}`);
  }
}

function checkLabelSummaries(v: unknown): void {
  need(Array.isArray(v), null, 'an array of labels', '/labels');
  (v as unknown[]).forEach((l, i) => {
    const label = need(isObject(l), l as Record<string, unknown>, 'a label', `/labels/${i}`);
    need(Number.isInteger(num(label, 'id', `/labels/${i}`)), null, 'an integer', `/labels/${i}/id`);
    str(label, 'name', `/labels/${i}`);
    numbers(label, 'color', `/labels/${i}`, 3);
    num(label, 'voxels', `/labels/${i}`);
  });
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
    case 'labels':
      str(o, 'session', '');
      str(o, 'volume', '');
      checkLabelSummaries(o['labels']);
      checkState(o['state'], '/state');
      return o as unknown as LabelsMessage;
    case 'picked': {
      str(o, 'session', '');
      num(o, 'x', '');
      num(o, 'y', '');
      if (bool(o, 'hit', '')) {
        numbers(o, 'position', '', 3);
        num(o, 'value', '');
        bool(o, 'hounsfield', '');
      }
      if (o['label'] !== undefined) {
        const label = obj(o, 'label', '');
        need(Number.isInteger(num(label, 'id', '/label')), null, 'an integer', '/label/id');
        str(label, 'name', '/label');
      }
      return o as unknown as PickedMessage;
    }
    case 'export_status': {
      str(o, 'export', '');
      oneOf(o['state'], EXPORT_STATES, '/state');
      num(o, 'progress', '');
      num(o, 'width', '');
      num(o, 'height', '');
      num(o, 'tiles', '');
      if (o['frames'] !== undefined) {
        num(o, 'frames', '');
      }
      if (o['url'] !== undefined) {
        str(o, 'url', '');
        num(o, 'bytes', '');
      }
      if (o['error'] !== undefined) {
        const error = obj(o, 'error', '');
        str(error, 'code', '/error');
        str(error, 'message', '/error');
      }
      return o as unknown as ExportStatusMessage;
    }
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

/** Each style of `styles` without the members `drop`, and without the styles left empty. */
function withoutStyleMembers(
  styles: Record<string, Partial<LabelStyle>> | undefined,
  drop: keyof LabelStyle,
): Record<string, Partial<LabelStyle>> | undefined {
  if (!styles) return undefined;
  const out: Record<string, Partial<LabelStyle>> = {};
  for (const [id, style] of Object.entries(styles)) {
    const rest = { ...style };
    delete rest[drop];
    if (Object.keys(rest).length > 0) out[id] = rest;
  }
  return Object.keys(out).length > 0 ? out : undefined;
}

/**
 * Two labels patches as one that does what `a` then `b` do. The server applies a patch's parts in
 * the order all, only, styles, blend, so a later `all` or `only` must drop what an earlier patch's
 * styles (or only) said of the same members: else they would be applied after it.
 */
export function mergeLabelsPatches(a: LabelsPatch, b: LabelsPatch): LabelsPatch {
  const out = structuredClone(a);
  const later = structuredClone(b);
  if (later.all) {
    if (later.all.visible !== undefined) {
      delete out.only;
      out.styles = withoutStyleMembers(out.styles, 'visible');
    }
    if (later.all.opacity !== undefined) {
      out.styles = withoutStyleMembers(out.styles, 'opacity');
    }
    out.all = { ...out.all, ...later.all };
  }
  if (later.only) {
    out.styles = withoutStyleMembers(out.styles, 'visible');
    out.only = later.only;
  }
  if (later.styles) {
    const styles = { ...out.styles };
    for (const [id, style] of Object.entries(later.styles)) {
      styles[id] = { ...styles[id], ...style };
    }
    out.styles = styles;
  }
  if (later.blend !== undefined) out.blend = later.blend;
  if (later.alone !== undefined) out.alone = later.alone;
  if (!out.styles) delete out.styles;
  return out;
}

/**
 * Two patches as one, the later winning member by member; a list (a vector, a size) and the
 * transfer function replace whole, and labels patches merge as mergeLabelsPatches says. What the
 * server makes of the result is its own: the client shows the state a `set` is answered with.
 */
export function mergePatches(a: StatePatch, b: StatePatch): StatePatch {
  const out = structuredClone(a) as Record<string, unknown>;
  for (const [key, value] of Object.entries(structuredClone(b))) {
    if (key === 'labels' && out['labels']) {
      out[key] = mergeLabelsPatches(out['labels'] as LabelsPatch, value as LabelsPatch);
    } else {
      out[key] = key === 'transfer_function' ? value : merged(out[key], value);
    }
  }
  return out as StatePatch;
}

function sameColor(a: Rgb, b: Rgb): boolean {
  return a.every((c, i) => Math.abs(c - b[i]!) < 1e-9);
}

/**
 * The labels patch that takes a map drawn with the styles `from` to those of `to`, short enough
 * for a message: what only differs, with `all` or `only` in place of a style for nearly every
 * label (a map of 724 labels, each hidden, is one `only`). Labels `from` lacks (another map) are
 * left out: the server refuses an id its map does not hold. Null when nothing differs.
 */
export function labelsPatchBetween(from: LabelsState, to: LabelsState): LabelsPatch | null {
  const ids = Object.keys(to.styles).filter((id) => from.styles[id] !== undefined);
  const patch: LabelsPatch = {};
  const styles: Record<string, Partial<LabelStyle>> = {};
  const style = (id: string): Partial<LabelStyle> => (styles[id] ??= {});

  const opacities = new Set(ids.map((id) => to.styles[id]!.opacity));
  const opacityChanged = ids.filter((id) => from.styles[id]!.opacity !== to.styles[id]!.opacity);
  if (opacities.size === 1 && opacityChanged.length > 1) {
    patch.all = { opacity: [...opacities][0]! };
  } else {
    for (const id of opacityChanged) style(id).opacity = to.styles[id]!.opacity;
  }

  const visible = ids.filter((id) => to.styles[id]!.visible);
  const visibilityChanged = ids.filter((id) => from.styles[id]!.visible !== to.styles[id]!.visible);
  if (visible.length === ids.length && visibilityChanged.length > 1) {
    patch.all = { ...patch.all, visible: true };
  } else if (visibilityChanged.length > visible.length + 1) {
    patch.only = visible.map(Number);
  } else {
    for (const id of visibilityChanged) style(id).visible = to.styles[id]!.visible;
  }

  for (const id of ids) {
    if (!sameColor(from.styles[id]!.color, to.styles[id]!.color)) {
      style(id).color = [...to.styles[id]!.color];
    }
  }
  if (Object.keys(styles).length > 0) patch.styles = styles;
  if (from.blend !== to.blend) patch.blend = to.blend;
  if ((from.alone ?? false) !== (to.alone ?? false)) patch.alone = to.alone ?? false;
  return Object.keys(patch).length > 0 ? patch : null;
}

/**
 * A `set` patch that restores `state` whole (what a reconnecting owner sends). Its labels go only
 * with `drawn`, the styles of the same map drawn again (add_labels' answer): the server refuses
 * labels while it draws no map, and a map's default styles need only what differs sent back.
 */
export function restorePatch(state: State, drawn?: LabelsState): StatePatch {
  const { labels, ...rest } = structuredClone(state);
  const patch: StatePatch = rest;
  const changed = labels && drawn ? labelsPatchBetween(drawn, labels) : null;
  if (changed) patch.labels = changed;
  return patch;
}

/**
 * `patch` without its labels where the server would refuse them, and the whole `set` with them:
 * while the session draws no map, or where they name an id its map lacks (another map's). What a
 * reconnecting owner still has to send goes through this once the session is restored.
 */
export function withoutRefusedLabels(patch: StatePatch, labels?: LabelsState): StatePatch | null {
  const named = [
    ...(patch.labels?.only ?? []).map(String),
    ...Object.keys(patch.labels?.styles ?? {}),
  ];
  if (!patch.labels || (labels && named.every((id) => labels.styles[id] !== undefined))) {
    return patch;
  }
  const rest = { ...patch };
  delete rest.labels;
  return Object.keys(rest).length > 0 ? rest : null;
}
