import { readdirSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import { orbitEye, orbitOf } from '../src/interaction/orbit_camera';
import {
  encodeClientMessage,
  labelsPatchBetween,
  mergeLabelsPatches,
  mergePatches,
  parseServerMessage,
  ProtocolError,
  restorePatch,
  SETTINGS,
  UnknownMessageType,
  type AckMessage,
  type ClientMessage,
  type HelloMessage,
  type LabelsMessage,
  type LabelsPatch,
  type LabelsState,
  type OpenedMessage,
  type PickedMessage,
  type State,
  type StateMessage,
  type StatePatch,
  type VolumesMessage,
  withoutRefusedLabels,
} from '../src/protocol/messages';
import { checkClientMessage, type ServerTerms } from './client_checks';
import { applyLabelsPatch } from './labels_server';
import { recordedHello, recordedLabelMessages, recordedMessages, recordedTerms } from './recorded';

const examples = path.resolve(__dirname, '../../proto/examples/v1');

function readJson(file: string): unknown {
  return JSON.parse(readFileSync(file, 'utf8'));
}

// The mode names the protocol defines; a server's hello lists those it offers.
const schemaModes = (
  readJson(path.resolve(__dirname, '../../proto/v1/common.schema.json')) as {
    $defs: { mode: { enum: string[] } };
  }
).$defs.mode.enum;

const valid = readdirSync(path.join(examples, 'valid')).filter((f) => f.endsWith('.json'));

/** The client message types the protocol defines (common.schema.json's client_type). */
const clientTypes = (
  readJson(path.resolve(__dirname, '../../proto/v1/common.schema.json')) as {
    $defs: { client_type: { enum: string[] } };
  }
).$defs.client_type.enum;

interface MessageSchema {
  examples?: unknown[];
  $defs?: { request?: MessageSchema };
}

/**
 * Each client message's main examples, from its schema (JSON Schema's `examples`): the whole
 * schema's, or those of `$defs/request` where one schema serves both directions (stats).
 */
const schemaExamples = clientTypes.map((type) => {
  const schema = readJson(
    path.resolve(__dirname, `../../proto/v1/${type}.schema.json`),
  ) as MessageSchema;
  const request = schema.$defs?.request ?? schema;
  const pointer = request === schema ? '' : '/$defs/request';
  return {
    type,
    name: `${type}.schema.json#${pointer}/examples`,
    examples: request.examples ?? [],
  };
});
const invalid = readdirSync(path.join(examples, 'invalid')).filter((f) => f.endsWith('.json'));
const serverMessages = recordedMessages;
/** What the server's hello says, with the mode names the protocol defines. */
const terms: ServerTerms = { ...recordedTerms, modes: schemaModes };
const parse = (text: string) => parseServerMessage(text);

describe("proto/v1: each client message's schema examples", () => {
  it.each(schemaExamples)('$name has an example of a $type message', ({ type, examples }) => {
    expect(examples.length).toBeGreaterThan(0);
    for (const example of examples) expect(example).toMatchObject({ type });
  });

  const cases = schemaExamples.flatMap(({ name, examples }) =>
    examples.map((message, index) => ({ name: `${name}/${index}`, message })),
  );
  it.each(cases)('$name is a client message the server accepts', ({ message }) => {
    expect(checkClientMessage(message, terms)).toBeNull();
    // Typed as a ClientMessage, it encodes back to the same JSON.
    expect(JSON.parse(encodeClientMessage(message as ClientMessage))).toEqual(message);
  });
});

describe('proto/examples/v1/valid', () => {
  it('has examples', () => expect(valid.length).toBeGreaterThan(20));

  it.each(valid)('%s is a client message the server accepts', (file) => {
    const message = readJson(path.join(examples, 'valid', file));
    expect(checkClientMessage(message, terms)).toBeNull();
    // Typed as a ClientMessage, it encodes back to the same JSON.
    const typed = message as ClientMessage;
    expect(JSON.parse(encodeClientMessage(typed))).toEqual(message);
  });
});

// What only the server can judge: integers as JSON text (512.0), ids beyond 2^53 that JSON.parse
// rounds, and texts that are not JSON at all (the "raw" examples).
const SERVER_ONLY = new Set([
  'id_beyond_int64.json',
  'size_written_as_float.json',
  'id_not_an_integer_fraction.json',
]);

describe('proto/examples/v1/invalid', () => {
  const cases = invalid
    .map((file) => ({
      file,
      example: readJson(path.join(examples, 'invalid', file)) as Record<string, unknown>,
    }))
    .filter(({ file, example }) => 'message' in example && !SERVER_ONLY.has(file));

  it('has examples to check', () => expect(cases.length).toBeGreaterThan(40));

  it.each(cases)('$file is rejected with the same code and field', ({ example }) => {
    const problem = checkClientMessage(example['message'], terms);
    expect(problem).not.toBeNull();
    expect({ code: problem?.code, field: problem?.field }).toEqual({
      code: example['code'],
      field: example['field'],
    });
  });
});

describe('checkClientMessage beyond the examples', () => {
  it('knows settings.frame_budget_ms (0..60000)', () => {
    const check = (ms: number) =>
      checkClientMessage({ v: 1, type: 'set', settings: { frame_budget_ms: ms } }, recordedTerms);
    expect(check(50)).toBeNull();
    expect(check(70000)).toMatchObject({
      code: 'out_of_range',
      field: '/settings/frame_budget_ms',
    });
  });

  it("checks ranges as the server's hello gives them", () => {
    const set = { v: 1, type: 'set', settings: { light_buffer: { slab_samples: 17 } } };
    expect(checkClientMessage(set, recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/settings/light_buffer/slab_samples',
    });
    const wider = {
      ...recordedTerms.ranges,
      'settings/light_buffer/slab_samples': { min: 0, max: 32, integer: true },
    };
    expect(checkClientMessage(set, { ...recordedTerms, ranges: wider })).toBeNull();
    const fraction = { v: 1, type: 'set', settings: { light_buffer: { slab_samples: 1.5 } } };
    expect(checkClientMessage(fraction, recordedTerms)).toMatchObject({ code: 'invalid_value' });
    const text = { v: 1, type: 'set', camera: { fov: '30' } };
    expect(checkClientMessage(text, recordedTerms)).toMatchObject({
      code: 'invalid_value',
      field: '/camera/fov',
    });
  });

  it("checks the JPEG quality by hello's range", () => {
    const set = (quality: number) => ({ v: 1, type: 'set', output: { jpeg_quality: quality } });
    expect(checkClientMessage(set(100), recordedTerms)).toBeNull();
    expect(checkClientMessage(set(101), recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/output/jpeg_quality',
    });
    expect(checkClientMessage(set(1.5), recordedTerms)).toMatchObject({ code: 'invalid_value' });
    const wider = {
      ...recordedTerms.ranges,
      'output/jpeg_quality': { min: 1, max: 120, integer: true },
    };
    expect(checkClientMessage(set(101), { ...recordedTerms, ranges: wider })).toBeNull();
  });

  it("checks the transfer function's colours by hello's colour range", () => {
    const colours = (c: number) => ({
      v: 1,
      type: 'set',
      transfer_function: { colors: [{ x: 0, rgb: [c, 0, 0] }], opacities: [] },
    });
    expect(checkClientMessage(colours(1), recordedTerms)).toBeNull();
    expect(checkClientMessage(colours(1.5), recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/transfer_function/colors/0/rgb/0',
    });
    const hdr = { ...recordedTerms.ranges, rgb: { min: 0, max: 2, integer: false } };
    expect(checkClientMessage(colours(1.5), { ...recordedTerms, ranges: hdr })).toBeNull();
  });

  it('knows the numbers of a set from the ranges alone: a new one needs no client change', () => {
    const set = (lb: Record<string, unknown>) => ({
      v: 1,
      type: 'set',
      settings: { light_buffer: lb },
    });
    // A setting the server does not announce is not one.
    expect(checkClientMessage(set({ glow: 2 }), recordedTerms)).toMatchObject({
      code: 'unknown_field',
      field: '/settings/light_buffer/glow',
    });
    const ranges = {
      ...recordedTerms.ranges,
      'settings/light_buffer/glow': { min: 0, max: 4, integer: false },
    };
    expect(
      checkClientMessage(set({ glow: 2, compensation: 3 }), { ...recordedTerms, ranges }),
    ).toBeNull();
    expect(checkClientMessage(set({ glow: 5 }), { ...recordedTerms, ranges })).toMatchObject({
      code: 'out_of_range',
      field: '/settings/light_buffer/glow',
    });
    // ... and so is a setting in a part of its own.
    const tone = {
      ...recordedTerms.ranges,
      'settings/tone/exposure': { min: -4, max: 4, integer: false },
    };
    const exposure = (value: unknown) => ({
      v: 1,
      type: 'set',
      settings: { tone: { exposure: value } },
    });
    expect(checkClientMessage(exposure(1), { ...recordedTerms, ranges: tone })).toBeNull();
    expect(checkClientMessage(exposure('1'), { ...recordedTerms, ranges: tone })).toMatchObject({
      code: 'invalid_value',
      field: '/settings/tone/exposure',
    });
    expect(checkClientMessage(exposure(1), recordedTerms)).toMatchObject({
      code: 'unknown_field',
      field: '/settings/tone',
    });
  });

  it('knows settings.empty_space_skipping', () => {
    const set = (value: unknown) => ({
      v: 1,
      type: 'set',
      settings: { empty_space_skipping: value },
    });
    expect(checkClientMessage(set(false), recordedTerms)).toBeNull();
    expect(checkClientMessage(set(1), recordedTerms)).toMatchObject({
      code: 'invalid_value',
      field: '/settings/empty_space_skipping',
    });
  });

  it('uses the limits from hello', () => {
    const limits = { ...recordedTerms.limits, max_image_side: 256 };
    const set = { v: 1, type: 'set', settings: { size: [300, 200] } };
    expect(checkClientMessage(set, recordedTerms)).toBeNull();
    expect(checkClientMessage(set, { ...recordedTerms, limits })).toMatchObject({
      code: 'out_of_range',
      field: '/settings/size/0',
    });
  });

  it("takes the transfer function's points, its Hounsfield reach and the strings' lengths from hello", () => {
    const announced = recordedTerms.limits;
    const tf = (n: number, x: number, space = 'hounsfield') => ({
      v: 1,
      type: 'set',
      transfer_function: {
        space,
        colors: [],
        opacities: Array.from({ length: n }, () => ({ x, alpha: 0.5 })),
      },
    });
    const most = announced.max_transfer_function_points;
    const reach = announced.max_hounsfield_position;
    expect(checkClientMessage(tf(most, reach), recordedTerms)).toBeNull();
    expect(checkClientMessage(tf(most + 1, 0), recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/transfer_function/opacities',
    });
    expect(checkClientMessage(tf(1, -reach * 1.5), recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/transfer_function/opacities/0/x',
    });
    // Another server's limits, not a copy of this one's.
    const fewer = { ...announced, max_transfer_function_points: 2, max_hounsfield_position: 10 };
    expect(checkClientMessage(tf(3, 0), { ...recordedTerms, limits: fewer })).toMatchObject({
      code: 'out_of_range',
    });
    expect(checkClientMessage(tf(1, 20), { ...recordedTerms, limits: fewer })).toMatchObject({
      code: 'out_of_range',
    });

    const bytes = announced.max_string_bytes;
    const open = (volume: string) => ({ v: 1, type: 'open', volume });
    expect(checkClientMessage(open('a'.repeat(bytes['open/volume']!)), recordedTerms)).toBeNull();
    expect(
      checkClientMessage(open('a'.repeat(bytes['open/volume']! + 1)), recordedTerms),
    ).toMatchObject({
      code: 'out_of_range',
      field: '/volume',
    });
    const resume = {
      v: 1,
      type: 'resume',
      session: 's',
      owner_token: 'a'.repeat(bytes['resume/owner_token']! + 1),
    };
    expect(checkClientMessage(resume, recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/owner_token',
    });
    const shorter = { ...announced, max_string_bytes: { ...bytes, 'join/session': 4 } };
    expect(
      checkClientMessage(
        { v: 1, type: 'join', session: 'abcde' },
        { ...recordedTerms, limits: shorter },
      ),
    ).toMatchObject({ code: 'out_of_range', field: '/session' });
    const named = {
      v: 1,
      type: 'set',
      transfer_function: { name: 'n'.repeat(bytes['set/transfer_function/name']! + 1) },
    };
    expect(checkClientMessage(named, recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/transfer_function/name',
    });
  });

  it("accepts the presets the server's hello names, and no other", () => {
    const preset = (name: string) => ({ v: 1, type: 'set', transfer_function: { preset: name } });
    for (const p of recordedHello.presets)
      expect(checkClientMessage(preset(p.name), recordedTerms)).toBeNull();
    expect(checkClientMessage(preset('ct_heart'), recordedTerms)).toMatchObject({
      code: 'invalid_value',
      field: '/transfer_function/preset',
    });
    expect(
      checkClientMessage(preset('ct_heart'), { ...recordedTerms, presets: ['ct_heart'] }),
    ).toBeNull();
  });
});

describe('parseServerMessage', () => {
  it('reads every message a real server sent', () => {
    const types = serverMessages.map((text) => parse(text).type);
    expect(types).toEqual(['hello', 'volumes', 'opened', 'ack', 'stats', 'error', 'state']);
  });

  it("reads whether the server's listing is complete, and nothing else for it", () => {
    const volumes = JSON.parse(serverMessages[1]!) as Record<string, unknown>;
    const read = parseServerMessage(JSON.stringify({ ...volumes, listing: 'scanning' }));
    expect(read.type === 'volumes' && read.listing).toBe('scanning');
    expect(() => parseServerMessage(JSON.stringify({ ...volumes, listing: 'done' }))).toThrow(
      '/listing',
    );
  });

  it('reads hello with the modes and limits', () => {
    const hello = parseServerMessage(serverMessages[0]!);
    if (hello.type !== 'hello') throw new Error('not hello');
    expect(hello.modes.map((m) => m.name)).toContain('sbrc_cone');
    expect(hello.modes).toHaveLength(7);
    expect(hello.modes.find((m) => m.name === 'sbrc_shell')).toMatchObject({
      shadows: 'light_buffer',
      scattering: 'shell',
    });
    expect(hello.limits.max_image_side).toBeGreaterThan(0);
    expect(hello.limits.max_sessions_per_client).toBeGreaterThan(0);
    expect(hello.limits.max_frame_work).toBeGreaterThan(0);
    expect(hello.ranges['settings/sample_distance']).toMatchObject({ integer: false });
    expect(hello.ranges['settings/scattering/shell_rings']).toMatchObject({
      min: 1,
      integer: true,
    });
  });

  it('rejects a hello without ranges or with a range that is not one', () => {
    const hello = JSON.parse(serverMessages[0]!) as Record<string, unknown>;
    const without = { ...hello };
    delete without['ranges'];
    expect(() => parseServerMessage(JSON.stringify(without))).toThrow(ProtocolError);
    const broken = { ...hello, ranges: { 'camera/fov': { min: 1, max: '170', integer: false } } };
    expect(() => parseServerMessage(JSON.stringify(broken))).toThrow(/max/);
  });

  it('needs the presets, the nominal CT range and the fixed limits of hello', () => {
    const hello = JSON.parse(serverMessages[0]!) as Record<string, unknown>;
    const read = parseServerMessage(serverMessages[0]!) as HelloMessage;
    expect(read.presets.length).toBeGreaterThan(0);
    expect(read.nominal_ct_range).toHaveLength(2);
    expect(read.limits.max_string_bytes['open/volume']).toBeGreaterThan(0);
    for (const member of ['presets', 'nominal_ct_range']) {
      const without = { ...hello };
      delete without[member];
      expect(() => parseServerMessage(JSON.stringify(without))).toThrow(`/${member}`);
    }
    const limits = hello['limits'] as Record<string, unknown>;
    for (const member of [
      'max_transfer_function_points',
      'max_hounsfield_position',
      'max_string_bytes',
    ]) {
      const fewer = { ...limits };
      delete fewer[member];
      expect(() => parseServerMessage(JSON.stringify({ ...hello, limits: fewer }))).toThrow(
        ProtocolError,
      );
    }
    const presets = structuredClone(read.presets) as unknown as Record<string, unknown>[];
    delete presets[1]!['opacities'];
    expect(() => parseServerMessage(JSON.stringify({ ...hello, presets }))).toThrow(
      '/presets/1/opacities',
    );
  });

  it('reads opened with a full state that checks as a set', () => {
    const opened = parse(serverMessages[2]!) as OpenedMessage;
    expect(opened.session.length).toBeGreaterThan(0);
    expect(opened.histogram.length).toBeGreaterThan(0);
    expect(opened.volume.dims).toEqual([181, 217, 181]);
    // "sending it back restores it"
    expect(
      checkClientMessage(
        { v: 1, type: 'set', id: 1, ...restorePatch(opened.state) },
        recordedTerms,
      ),
    ).toBeNull();
  });

  it("reads opened's owner token, which resume takes back", () => {
    const opened = parse(serverMessages[2]!) as OpenedMessage;
    expect(opened.owner_token).toMatch(/^[0-9a-f]{32}$/);
    const resume = {
      v: 1,
      type: 'resume',
      session: opened.session,
      owner_token: opened.owner_token,
    };
    expect(checkClientMessage(resume, recordedTerms)).toBeNull();
    const withNumber = { ...(JSON.parse(serverMessages[2]!) as object), owner_token: 5 };
    expect(() => parse(JSON.stringify(withNumber))).toThrow(/owner_token/);
  });

  it("reads state, the owner's change that a viewer gets, in the shape of opened's state", () => {
    const message = parse(serverMessages[6]!) as StateMessage;
    expect(message.type).toBe('state');
    expect(message.session.length).toBeGreaterThan(0);
    expect('id' in message).toBe(false);
    const opened = parse(serverMessages[2]!) as OpenedMessage;
    expect(Object.keys(message.state).sort()).toEqual(Object.keys(opened.state).sort());
    expect(message.state.settings.mode).not.toBe(opened.state.settings.mode);
    expect(
      checkClientMessage({ v: 1, type: 'set', ...restorePatch(message.state) }, recordedTerms),
    ).toBeNull();
  });

  it("checks a state by the server's table: every setting there, of its kind", () => {
    const opened = JSON.parse(serverMessages[2]!) as {
      state: { settings: Record<string, unknown> };
    };
    const withLightBuffer = (lb: Record<string, unknown>) => {
      const copy = structuredClone(opened);
      copy.state.settings['light_buffer'] = {
        ...(copy.state.settings['light_buffer'] as object),
        ...lb,
      };
      return JSON.stringify(copy);
    };
    expect(() => parse(withLightBuffer({ compensation: 'high' }))).toThrow(
      /expected a number \(at \/state\/settings\/light_buffer\/compensation\)/,
    );
    expect(() => parse(withLightBuffer({ slab_samples: 1.5 }))).toThrow(
      /expected an integer \(at \/state\/settings\/light_buffer\/slab_samples\)/,
    );
    expect(() => parse(withLightBuffer({ builder: 3 }))).toThrow(
      /\/state\/settings\/light_buffer\/builder/,
    );
    const missing = structuredClone(opened);
    delete (missing.state.settings['shading'] as Record<string, unknown>)['specular'];
    expect(() => parse(JSON.stringify(missing))).toThrow(/\/state\/settings\/shading\/specular/);
    const flat = structuredClone(opened);
    flat.state.settings['background'] = [0, 0];
    expect(() => parse(JSON.stringify(flat))).toThrow(/\/state\/settings\/background/);
    // Every setting the table lists is one a recorded state holds.
    const state = (parse(serverMessages[2]!) as OpenedMessage).state as unknown as Record<
      string,
      unknown
    >;
    for (const path of Object.keys(SETTINGS)) {
      const value = path
        .split('/')
        .reduce<unknown>((at, part) => (at as Record<string, unknown>)[part], state);
      expect(value, path).toBeDefined();
    }
  });

  it("reads a set's ack with the state the server made of the patch", () => {
    const opened = JSON.parse(serverMessages[2]!) as { state: State };
    const ack = parse(
      JSON.stringify({ v: 1, type: 'ack', id: 4, of: 'set', state: opened.state }),
    ) as AckMessage;
    expect(ack.state).toEqual(opened.state);
    const broken = { ...opened.state, camera: { ...opened.state.camera, eye: [0, 0] } };
    expect(() => parse(JSON.stringify({ v: 1, type: 'ack', of: 'set', state: broken }))).toThrow(
      /\/state\/camera\/eye/,
    );
  });

  it('reads a range with its summary, and refuses a summary that is not text', () => {
    const hello = JSON.parse(serverMessages[0]!) as Record<string, unknown>;
    const range = { min: 0, max: 1000, integer: false, summary: 'compensation n' };
    const withSummary = { ...hello, ranges: { 'settings/light_buffer/compensation': range } };
    expect((parse(JSON.stringify(withSummary)) as HelloMessage).ranges).toEqual(withSummary.ranges);
    const broken = {
      ...hello,
      ranges: { 'camera/fov': { min: 1, max: 170, integer: false, summary: 3 } },
    };
    expect(() => parse(JSON.stringify(broken))).toThrow(/\/ranges\/camera\/fov\/summary/);
  });

  it('ignores members it does not know (the server may add some within v1)', () => {
    const ack = parseServerMessage('{"v":1,"type":"ack","id":3,"of":"set","later":true}');
    expect(ack).toMatchObject({ type: 'ack', of: 'set' });
  });

  it.each([
    ['not JSON', '{', '/'],
    ['another version', '{"v":2,"type":"ack","of":"set"}', '/v'],
    ['no type', '{"v":1}', '/type'],
    ['an unknown type', '{"v":1,"type":"surprise"}', '/type'],
    ['an error without code', '{"v":1,"type":"error","message":"m","field":""}', '/code'],
    [
      'opened without state',
      '{"v":1,"type":"opened","session":"s","volume":{},"histogram":[]}',
      '/volume/id',
    ],
    ['state without state', '{"v":1,"type":"state","session":"s"}', '/state'],
    ['state without session', '{"v":1,"type":"state","state":{}}', '/session'],
  ])('rejects %s', (_, text, field) => {
    try {
      parse(text);
      expect.unreachable();
    } catch (e) {
      expect(e).toBeInstanceOf(ProtocolError);
      expect((e as ProtocolError).field).toBe(field);
      expect(e instanceof UnknownMessageType).toBe(text.includes('surprise'));
    }
  });
});

describe('patches', () => {
  const opened = parse(serverMessages[2]!) as OpenedMessage;
  const state: State = opened.state;

  it('puts an orbit eye where the server does', () => {
    // The default camera of the server: the anterior view (azimuth 0: +y), elevation 0, distance
    // 2.6 (see opened).
    const eye = orbitEye([0, 0, 0], { azimuth: 0, elevation: 0, distance: 2.6 });
    state.camera.eye.forEach((c, i) => expect(eye[i]).toBeCloseTo(c, 9));
    const orbit = orbitOf(state.camera.eye, state.camera.target);
    expect(orbit.azimuth).toBeCloseTo(0, 9);
    expect(orbit.elevation).toBeCloseTo(0, 9);
    expect(orbit.distance).toBeCloseTo(2.6, 9);
  });

  it('merges patches member by member, the later winning; lists and the transfer function replace', () => {
    const merged = mergePatches(
      {
        camera: { eye: [1, 0, 0], fov: 30 },
        settings: { light_buffer: { slices: 8 }, mode: 'dvr', size: [64, 64] },
        transfer_function: { preset: 'ct_bone' },
      },
      {
        camera: { eye: [0, 1, 0] },
        settings: { light_buffer: { resolution: 64 }, size: [32, 16] },
        transfer_function: { opacities: [{ x: 0.5, alpha: 1 }] },
      },
    );
    expect(merged).toEqual({
      camera: { eye: [0, 1, 0], fov: 30 },
      settings: { mode: 'dvr', size: [32, 16], light_buffer: { slices: 8, resolution: 64 } },
      transfer_function: { opacities: [{ x: 0.5, alpha: 1 }] },
    });
  });

  it('restores a state whole, as a set the server takes', () => {
    expect(restorePatch(state)).toEqual(state);
    expect(
      checkClientMessage({ v: 1, type: 'set', ...restorePatch(state) }, recordedTerms),
    ).toBeNull();
  });
});

describe('label maps and picks', () => {
  const messages = recordedLabelMessages.map((text) => parse(text));
  const added = messages[0] as LabelsMessage;
  const defaults = added.state.labels!;
  const acked = (messages[2] as AckMessage).state!;

  it('reads every label-map message a real server sent', () => {
    expect(messages.map((m) => [m.type, 'id' in m])).toEqual([
      ['labels', true],
      ['labels', false], // after joined: no request answered
      ['ack', true],
      ['state', false],
      ['picked', true],
      ['picked', true],
      ['labels', true],
    ]);
  });

  it("reads labels: the map, each label's name, colour and voxels, and the state styling them", () => {
    expect(added.volume).toBe('aal.nii.gz');
    expect(added.labels).toHaveLength(116);
    expect(added.labels[44]).toEqual({
      id: 45,
      name: 'Cuneus_L',
      color: expect.any(Array) as number[],
      voxels: expect.any(Number) as number,
    });
    expect(Object.keys(defaults.styles)).toHaveLength(116);
    expect(defaults.blend).toBe(0.6);
    expect(defaults.styles['1']).toEqual({ color: [0.8, 0.8, 0.8], opacity: 1, visible: true });
    const removed = messages[6] as LabelsMessage;
    expect(removed).toMatchObject({ volume: '', labels: [] });
    expect(removed.state.labels).toBeUndefined();
  });

  it("reads a state's labels in an ack and in a viewer's state", () => {
    expect(acked.labels!.blend).toBe(0.8);
    expect(acked.labels!.styles['46']).toMatchObject({ opacity: 0.5, visible: true });
    expect((messages[3] as StateMessage).state.labels).toEqual(acked.labels);
  });

  it('reads picked: with a hit where, what value and which label; without, only the point', () => {
    const hit = messages[4] as PickedMessage;
    expect(hit).toMatchObject({ hit: true, hounsfield: false, label: { id: 19 } });
    expect(hit.position).toHaveLength(3);
    expect(typeof hit.value).toBe('number');
    const miss = messages[5] as PickedMessage;
    expect(miss).toMatchObject({ hit: false, x: 0.02, y: 0.02 });
    expect(miss.position).toBeUndefined();
  });

  it.each([
    ['a label without a name', 'labels', '/labels/3/name'],
    ['a label whose id is a fraction', 'labels', '/labels/3/id'],
    ['a style without visibility', 'labels', '/state/labels/styles/4/visible'],
    ['a style keyed by a name', 'labels', '/state/labels/styles'],
    ['a hit without a position', 'picked', '/position'],
    ['a label without an id', 'picked', '/label/id'],
  ])('rejects %s', (what, type, field) => {
    const message = JSON.parse(recordedLabelMessages[type === 'labels' ? 0 : 4]!) as Record<
      string,
      unknown
    > & {
      labels: Record<string, unknown>[];
      state: { labels: { styles: Record<string, Record<string, unknown>> } };
      label: Record<string, unknown>;
    };
    if (what === 'a label without a name') delete message.labels[3]!['name'];
    if (what === 'a label whose id is a fraction') message.labels[3]!['id'] = 4.5;
    if (what === 'a style without visibility') delete message.state.labels.styles['4']!['visible'];
    if (what === 'a style keyed by a name') message.state.labels.styles['Cuneus_L'] = {};
    if (what === 'a hit without a position') delete message['position'];
    if (what === 'a label without an id') delete message.label['id'];
    expect(() => parse(JSON.stringify(message))).toThrow(field);
  });

  it('reads whether a listed volume is a label map, where the server says', () => {
    const volumes = JSON.parse(serverMessages[1]!) as VolumesMessage;
    volumes.volumes[0]!.label_map = true;
    const read = parse(JSON.stringify(volumes)) as VolumesMessage;
    expect(read.volumes[0]!.label_map).toBe(true);
    expect(read.volumes[1]!.label_map).toBeUndefined();
    (volumes.volumes[1] as unknown as Record<string, unknown>)['label_map'] = 'yes';
    expect(() => parse(JSON.stringify(volumes))).toThrow('/volumes/1/label_map');
  });

  it('add_labels, remove_labels and pick are messages the server accepts', () => {
    for (const message of [
      { v: 1, type: 'add_labels', id: 1, volume: 'aal.nii.gz' },
      { v: 1, type: 'remove_labels', id: 2 },
      { v: 1, type: 'pick', id: 3, x: 0.5, y: 0.42 },
    ] as ClientMessage[]) {
      expect(checkClientMessage(JSON.parse(encodeClientMessage(message)), terms)).toBeNull();
    }
  });
});

describe('labels patches', () => {
  const added = parse(recordedLabelMessages[0]!) as LabelsMessage;
  const defaults = added.state.labels!;
  const acked = (parse(recordedLabelMessages[2]!) as AckMessage).state!;

  /** A few patches of each kind the panel sends, on ids of the map. */
  const kinds: LabelsPatch[] = [
    { all: { visible: false } },
    { all: { visible: true } },
    { all: { opacity: 0.3 } },
    { only: [45] },
    { only: [45, 46, 67] },
    { styles: { '45': { visible: false } } },
    { styles: { '46': { visible: true, opacity: 0.2 } } },
    { styles: { '45': { opacity: 0.7 } } },
    { blend: 0.25 },
    { alone: true },
    { alone: false, only: [46] },
    { all: { opacity: 1, visible: true }, only: [46], styles: { '46': { opacity: 0.4 } } },
  ];

  it('merged, do what the first and then the second do, in the order the server applies a patch', () => {
    for (const a of kinds) {
      for (const b of kinds) {
        const sequential = applyLabelsPatch(applyLabelsPatch(defaults, a), b);
        const merged = mergeLabelsPatches(a, b);
        expect(applyLabelsPatch(defaults, merged), JSON.stringify([a, b])).toEqual(sequential);
      }
    }
    // As part of a set's patch, next to the other parts.
    expect(
      mergePatches(
        { camera: { fov: 30 }, labels: { styles: { '45': { visible: false } } } },
        { labels: { only: [46] } },
      ),
    ).toEqual({ camera: { fov: 30 }, labels: { only: [46] } });
  });

  it('between two styles of a map take the first to the second, briefly', () => {
    const patch = labelsPatchBetween(defaults, acked.labels!)!;
    expect(patch).toEqual({ only: [45, 46, 57], styles: { '46': { opacity: 0.5 } }, blend: 0.8 });
    expect(applyLabelsPatch(defaults, patch)).toEqual(acked.labels);
    expect(labelsPatchBetween(defaults, defaults)).toBeNull();
    const back = labelsPatchBetween(acked.labels!, defaults)!;
    expect(applyLabelsPatch(acked.labels!, back)).toEqual(defaults);
    expect(back.all).toEqual({ visible: true });
    // A map drawn alone is drawn alone again.
    const alone = { ...acked.labels!, alone: true };
    expect(labelsPatchBetween(defaults, alone)!.alone).toBe(true);
    expect(applyLabelsPatch(defaults, labelsPatchBetween(defaults, alone)!)).toEqual(alone);
    expect(labelsPatchBetween(alone, acked.labels!)!.alone).toBe(false);
  });

  it('between styles of an atlas of hundreds of labels fit in a message', () => {
    const many: LabelsState = { blend: 0.6, styles: {} };
    for (let id = 1; id <= 724; ++id) {
      many.styles[String(id)] = {
        color: [0.123456789, 0.5, 0.987654321],
        opacity: 1,
        visible: true,
      };
    }
    const some = structuredClone(many);
    for (const [id, style] of Object.entries(some.styles)) {
      style.visible = Number(id) % 7 === 0;
      style.opacity = Number(id) % 3 === 0 ? 0.5 : 1;
    }
    const patch = labelsPatchBetween(many, some)!;
    expect(applyLabelsPatch(many, patch)).toEqual(some);
    const text = encodeClientMessage({ v: 1, type: 'set', id: 1, labels: patch });
    expect(text.length).toBeLessThan(recordedHello.limits.max_message_bytes / 4);
    expect(checkClientMessage(JSON.parse(text), terms)).toBeNull();
  });

  it('leave out the labels the map drawn again does not hold (the server refuses an id it lacks)', () => {
    const fewer: LabelsState = { blend: 0.6, styles: { '45': defaults.styles['45']! } };
    const patch = labelsPatchBetween(fewer, acked.labels!)!;
    expect(patch).toEqual({ blend: 0.8 });
    expect(() => applyLabelsPatch(fewer, patch)).not.toThrow();
  });

  it('are no part of a restore until the map is drawn again, then only what differs', () => {
    const withLabels: State = acked;
    const withoutMap = restorePatch(withLabels);
    expect(withoutMap.labels).toBeUndefined();
    expect(Object.keys(withoutMap).sort()).toEqual(
      ['camera', 'cut', 'light', 'output', 'settings', 'transfer_function'].sort(),
    );
    const drawnAgain = restorePatch(withLabels, defaults);
    expect(drawnAgain.labels).toEqual(labelsPatchBetween(defaults, acked.labels!));
    expect(
      checkClientMessage({ v: 1, type: 'set', id: 1, ...drawnAgain }, recordedTerms),
    ).toBeNull();
    // The same styles as the map's own: nothing of them to send.
    expect(restorePatch({ ...withLabels, labels: defaults }, defaults).labels).toBeUndefined();
  });

  it('made while disconnected are left out once restored where the server would refuse them', () => {
    const size: StatePatch = { settings: { size: [640, 480] } };
    for (const labels of kinds) {
      const patch = mergePatches({ camera: { fov: 40 }, labels }, size);
      // The same map drawn again: they go, and the server takes them.
      const kept = withoutRefusedLabels(patch, defaults)!;
      expect(kept).toEqual(patch);
      expect(() => applyLabelsPatch(defaults, kept.labels!)).not.toThrow();
      // No map drawn (not drawn again, or removed meanwhile): the rest goes without them.
      expect(withoutRefusedLabels(patch, undefined)).toEqual({ camera: { fov: 40 }, ...size });
    }
    // Another map: what names an id it lacks goes; what names none of its ids stays.
    const other: LabelsState = { blend: 0.5, styles: { '45': defaults.styles['45']! } };
    expect(withoutRefusedLabels({ ...size, labels: { only: [45, 46] } }, other)).toEqual(size);
    expect(
      withoutRefusedLabels({ labels: { styles: { '46': { opacity: 0 } } } }, other),
    ).toBeNull();
    const bulk: StatePatch = { labels: { all: { visible: false }, only: [45], blend: 0.2 } };
    expect(withoutRefusedLabels(bulk, other)).toEqual(bulk);
    expect(withoutRefusedLabels(size, undefined)).toBe(size);
  });
});
