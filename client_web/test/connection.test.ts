import { readFileSync } from 'node:fs';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import {
  Connection,
  RequestFailed,
  routedUrl,
  ServerError,
  type ConnectionOptions,
  type ConnectionStatus,
  type SocketLike,
} from '../src/protocol/connection';
import { packFrame, type FrameHeader } from '../src/protocol/frame_header';
import { mergePatches, type State, type StatePatch } from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { RenderPacer } from '../src/interaction/pacing';
import { recordedHello, recordedLabelMessages, recordedTerms } from './recorded';
import { FakeClock } from './fake_timers';

const recorded = readFileSync(path.join(__dirname, 'fixtures/server_messages.jsonl'), 'utf8')
  .split('\n')
  .filter((l) => l !== '');
const HELLO = recorded[0]!;
const OPENED = JSON.parse(recorded[2]!) as Record<string, unknown>;
const OWNER_TOKEN = OPENED['owner_token'] as string;
/** `opened` as a server older than resume sends it: without an owner token. */
const OPENED_WITHOUT_TOKEN = Object.fromEntries(
  Object.entries(OPENED).filter(([key]) => key !== 'owner_token'),
);

/** AAL drawn over ch2 (recorded.ts says what each is), each without its id and session. */
const [LABELS_ADDED, LABELS_AFTER_JOIN, ACKED_LABELS, , PICKED_HIT, , LABELS_REMOVED] =
  recordedLabelMessages.map((text) => {
    const message = JSON.parse(text) as Record<string, unknown>;
    delete message['id'];
    delete message['session'];
    return message;
  });
/** The state after the owner showed labels 45, 46 and 57 alone, 46 half opaque, blend 0.8. */
const LABELLED_STATE = ACKED_LABELS!['state'] as State;

class FakeSocket implements SocketLike {
  binaryType = 'blob';
  readyState = 0;
  onopen: SocketLike['onopen'] = null;
  onclose: SocketLike['onclose'] = null;
  onerror: SocketLike['onerror'] = null;
  onmessage: SocketLike['onmessage'] = null;
  sent: Record<string, unknown>[] = [];

  constructor(readonly url: string) {}

  send(data: string): void {
    const message = JSON.parse(data) as Record<string, unknown>;
    // Everything the client sends must be a message the server accepts.
    expect(checkClientMessage(message, recordedTerms)).toBeNull();
    this.sent.push(message);
  }

  close(code = 1000, reason = ''): void {
    this.readyState = 3;
    this.onclose?.({ code, reason });
  }

  // server side
  open(): void {
    this.readyState = 1;
    this.onopen?.({});
    this.receive(HELLO);
  }

  receive(data: string | ArrayBuffer): void {
    this.onmessage?.({ data });
  }

  reply(type: string, extra: Record<string, unknown> = {}): void {
    const last = this.sent[this.sent.length - 1]!;
    if (extra['state'] !== undefined) this.state = structuredClone(extra['state']) as State;
    this.receive(JSON.stringify({ v: 1, ...extra, type, id: last['id'] }));
  }

  /** The session's state as this fake server holds it: the last one it sent. */
  state: State | null = null;

  /**
   * Answers the last `set` as the server does, with the state the patch makes: its members in
   * place, a preset's points as hello announced them.
   */
  ackSet(): void {
    const patch = { ...this.sent[this.sent.length - 1]! } as Record<string, unknown> & StatePatch;
    for (const envelope of ['v', 'type', 'id']) delete patch[envelope];
    let state = mergePatches(this.state as StatePatch, patch) as State;
    const tf = patch.transfer_function;
    if (tf && 'preset' in tf) {
      state = {
        ...state,
        transfer_function: structuredClone(
          recordedHello.presets.find((p) => p.name === tf.preset)!,
        ),
      };
    }
    this.reply('ack', { of: 'set', state });
  }

  fail(reason = ''): void {
    this.readyState = 3;
    this.onclose?.({ code: 1006, reason });
  }
}

function setup(extra: ConnectionOptions = {}) {
  const clock = new FakeClock();
  const sockets: FakeSocket[] = [];
  const statuses: ConnectionStatus['kind'][] = [];
  const connection = new Connection('ws://test/ws', {
    // The volume the tests open: its WebSocket serves it.
    route: { volume: 'ch2.nii.gz' },
    ...extra,
    createSocket: (url) => {
      const s = new FakeSocket(url);
      sockets.push(s);
      return s;
    },
    reconnectDelaysMs: [100, 200],
    requestTimeoutMs: 1000,
    setTimer: clock.setTimer,
    clearTimer: clock.clearTimer,
  });
  connection.on('status', (s) => statuses.push(s.kind));
  connection.connect();
  const socket = (): FakeSocket => sockets[sockets.length - 1]!;
  return { clock, sockets, socket, statuses, connection };
}

const flush = (): Promise<void> => new Promise((r) => setTimeout(r, 0));

const frameHeader: FrameHeader = {
  frame: 1,
  request: 5,
  session: 's',
  width: 1,
  height: 1,
  encoding: 'jpeg',
  mode: 'dvr',
  interactive: false,
  light_buffer: 'none',
  passes: [],
  timings: { queued_ms: 0, render_ms: 0, readback_ms: 0, encode_ms: 0 },
  quality: '',
};

describe('Connection', () => {
  it('connects, reads hello and matches answers to requests by id', async () => {
    const { socket, statuses, connection } = setup();
    expect(socket().binaryType).toBe('arraybuffer');
    socket().open();
    expect(statuses).toEqual(['connecting', 'connected']);
    expect(connection.hello?.modes).toHaveLength(7);
    const volumes = connection.listVolumes();
    expect(socket().sent[0]).toEqual({ v: 1, id: 1, type: 'list_volumes' });
    socket().receive(recorded[1]!);
    const listed = await volumes;
    expect(listed.volumes.map((v) => v.id)).toContain('AICHAmc.nii.gz');
    expect(listed.listing).toBe('complete');
  });

  it('sends any request through request() and resolves with the answer its type takes', async () => {
    const { socket, connection } = setup();
    socket().open();
    const stats = connection.request({ type: 'stats' });
    expect(socket().sent[0]).toEqual({ v: 1, id: 1, type: 'stats' });
    socket().reply('stats', { stats: { frames: 3 } });
    expect((await stats).stats).toEqual({ frames: 3 });
    // An answer of another type is no answer to it.
    const volumes = connection.request({ type: 'list_volumes' });
    socket().reply('ack', { of: 'list_volumes' });
    const error = await volumes.catch((e: unknown) => e);
    expect(error).toBeInstanceOf(RequestFailed);
    expect((error as Error).message).toBe('list_volumes answered by ack');
  });

  it('rejects a request answered by an error with the server code and field', async () => {
    const { socket, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const set = connection.set({ camera: { eye: [0, 0, 0] } }); // the target: only the server knows
    socket().reply('error', {
      code: 'invalid_value',
      field: '/camera',
      message: 'eye equals target',
    });
    const error = await set.catch((e: unknown) => e);
    expect(error).toBeInstanceOf(ServerError);
    expect((error as ServerError).describe()).toBe(
      'invalid_value at /camera (set): eye equals target',
    );
    expect(connection.session?.state.camera.eye[1]).toBeGreaterThan(2); // the mirror keeps what the server has
  });

  it('keeps the state mirror in step with acknowledged sets', async () => {
    const { socket, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    expect((await opened).role).toBe('owner');
    const set = connection.set({ settings: { mode: 'phong', light_buffer: { slices: 32 } } });
    socket().ackSet();
    await set;
    expect(connection.session?.state.settings.mode).toBe('phong');
    expect(connection.session?.state.settings.light_buffer.slices).toBe(32);
  });

  it("a viewer's mirror follows the states its owner sets", async () => {
    const { socket, connection } = setup();
    socket().open();
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    const states: string[] = [];
    connection.on('state', (info) => states.push(`${info.role} ${info.state.settings.mode}`));
    const joined = connection.join('abc');
    socket().reply('joined', { ...OPENED, session: 'abc' });
    await joined;
    const state = structuredClone(OPENED['state']) as State;
    state.settings.mode = 'dvr';
    state.light.direction = [0, -1, 0.5];
    socket().receive(JSON.stringify({ v: 1, type: 'state', session: 'abc', state }));
    expect(states).toEqual(['viewer dvr']);
    expect(connection.session?.state).toEqual(state);
    // One of a session left behind, still on its way, changes nothing.
    socket().receive(
      JSON.stringify({ v: 1, type: 'state', session: 'old', state: OPENED['state'] }),
    );
    expect(states).toHaveLength(1);
    expect(connection.session?.state.settings.mode).toBe('dvr');
    expect(problems).toEqual([]);
  });

  it('an owner keeps the mirror of its own acknowledged sets', async () => {
    const { socket, connection } = setup();
    socket().open();
    const states: string[] = [];
    connection.on('state', (info) => states.push(info.state.settings.mode));
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    const session = (await opened).session;
    const state = structuredClone(OPENED['state']) as State;
    state.settings.mode = 'dvr';
    socket().receive(JSON.stringify({ v: 1, type: 'state', session, state }));
    expect(states).toEqual([]);
    expect(connection.session?.state.settings.mode).toBe((OPENED['state'] as State).settings.mode);
  });

  it('delivers frames and reports errors of renders without a pending request', () => {
    const { socket, connection } = setup();
    socket().open();
    const frames: number[] = [];
    const errors: string[] = [];
    connection.on('frame', (f) => frames.push(f.header.request));
    connection.on('serverError', (e) => errors.push(`${e.code} ${e.requestType ?? '-'}`));
    const id = connection.render(true);
    expect(socket().sent[0]).toEqual({ v: 1, id, type: 'render', interactive: true });
    socket().receive(
      JSON.stringify({
        v: 1,
        type: 'error',
        id,
        code: 'no_session',
        message: 'open first',
        field: '/type',
      }),
    );
    socket().receive(packFrame(frameHeader, new Uint8Array([0xff, 0xd8])).buffer as ArrayBuffer);
    socket().receive(
      JSON.stringify({ v: 1, type: 'error', code: 'render_failed', message: 'GL', field: '' }),
    );
    expect(frames).toEqual([5]);
    expect(errors).toEqual(['no_session render', 'render_failed -']);
  });

  it("answers a pacer's render by the error that carries its id, so the next wish is sent", async () => {
    const { clock, socket, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const pacer = new RenderPacer((interactive) => connection.render(interactive), {
      minIntervalMs: 0,
      now: () => clock.now,
      setTimer: clock.setTimer,
      clearTimer: clock.clearTimer,
    });
    pacer.listenTo(connection);
    const failed: string[] = [];
    connection.on('renderFailed', (id, e) =>
      failed.push(`${id} ${e.code} ${e.requestType ?? '-'}`),
    );
    const renders = () =>
      socket()
        .sent.filter((m) => m['type'] === 'render')
        .map((m) => m['id'] as number);
    pacer.request(false);
    pacer.request(false);
    pacer.request(false); // waits: two are in flight
    const [first, second] = renders();
    expect(renders()).toHaveLength(2);
    expect(pacer.hasWanted).toBe(true);
    const refused = {
      v: 1,
      type: 'error',
      code: 'too_much_work',
      message: 'estimate 2e11 > 1e11',
      field: '',
    };
    socket().receive(JSON.stringify({ ...refused, id: second }));
    // The refused render and the older one it superseded are answered: the wish goes out.
    expect(failed).toEqual([`${second} too_much_work render`]);
    expect(pacer.inFlight).toBe(1);
    expect(renders()).toHaveLength(3);
    expect(pacer.hasWanted).toBe(false);
    const third = renders()[2]!;
    socket().receive(
      JSON.stringify({
        v: 1,
        type: 'error',
        id: third,
        code: 'render_failed',
        message: 'GL [x]',
        field: '',
      }),
    );
    expect(failed).toEqual([`${second} too_much_work render`, `${third} render_failed render`]);
    expect(pacer.inFlight).toBe(0);
    // An error for no render of its own (another request's id, or none) answers none.
    socket().receive(JSON.stringify({ ...refused, id: first }));
    socket().receive(JSON.stringify({ ...refused }));
    expect(failed).toHaveLength(2);
  });

  it('answers only the render a rate_limited error names: the older ones are still queued', async () => {
    const { clock, socket, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const pacer = new RenderPacer((interactive) => connection.render(interactive), {
      maxInFlight: 3,
      minIntervalMs: 0,
      now: () => clock.now,
      setTimer: clock.setTimer,
      clearTimer: clock.clearTimer,
    });
    pacer.listenTo(connection);
    const failed: string[] = [];
    connection.on('renderFailed', (id, e) => failed.push(`${id} ${e.code}`));
    const renders = () =>
      socket()
        .sent.filter((m) => m['type'] === 'render')
        .map((m) => m['id'] as number);
    pacer.request(false);
    pacer.request(false);
    pacer.request(false);
    const [first, second, third] = renders();
    expect(renders()).toHaveLength(3);
    const error = (id: number, code: string) =>
      JSON.stringify({ v: 1, type: 'error', id, code, message: 'm', field: '/' });
    socket().receive(error(third!, 'rate_limited'));
    expect(failed).toEqual([`${third} rate_limited`]);
    expect(pacer.inFlight).toBe(2);
    // The older two are still the connection's renders: the scheduler's answers to them count.
    socket().receive(error(first!, 'render_failed'));
    expect(failed).toEqual([`${third} rate_limited`, `${first} render_failed`]);
    expect(pacer.inFlight).toBe(1);
    socket().receive(
      packFrame({ ...frameHeader, request: second! }, new Uint8Array([0xff, 0xd8]))
        .buffer as ArrayBuffer,
    );
    expect(pacer.inFlight).toBe(0);
  });

  it("mirrors a preset as the server's hello announced it", async () => {
    const { socket, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const preset = recordedHello.presets.find((p) => p.space === 'hounsfield')!;
    const set = connection.set({ transfer_function: { preset: preset.name } });
    socket().ackSet();
    await set;
    expect(connection.session?.state.transfer_function).toEqual(preset);
  });

  it('reports a server that cannot be reached and keeps trying', () => {
    const { clock, sockets, socket, statuses } = setup();
    socket().fail('refused');
    expect(statuses).toEqual(['connecting', 'unreachable']);
    clock.advance(100);
    expect(sockets).toHaveLength(2);
    socket().fail();
    clock.advance(199);
    expect(sockets).toHaveLength(2);
    clock.advance(1);
    expect(sockets).toHaveLength(3);
    socket().open();
    expect(statuses.slice(-1)).toEqual(['connected']);
  });

  it('after a lost connection re-opens the volume and sends the state back (no owner token)', async () => {
    const { clock, socket, statuses, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED_WITHOUT_TOKEN);
    expect((await opened).ownerToken).toBeUndefined();
    const set = connection.set({ settings: { mode: 'sbrc_cone' } });
    socket().ackSet();
    await set;
    const pending = connection.stats();
    socket().fail();
    expect(await pending.catch((e: unknown) => e)).toBeInstanceOf(RequestFailed);
    expect(statuses.slice(-1)).toEqual(['lost']);
    const restored: (string | false)[] = [];
    connection.on('session', (_, r) => {
      restored.push(r);
      expect(connection.restoring).toBe(false); // the listener may send at once
    });
    clock.advance(100);
    socket().open();
    expect(socket().sent[0]).toMatchObject({ type: 'open', volume: 'ch2.nii.gz' });
    expect(connection.restoring).toBe(true);
    socket().reply('opened', { ...OPENED, session: 'new-session' });
    await flush();
    const restore = socket().sent[1]!;
    expect(restore['type']).toBe('set');
    expect((restore['settings'] as Record<string, unknown>)['mode']).toBe('sbrc_cone');
    expect(Object.keys(restore).sort()).toEqual([
      'camera',
      'cut',
      'id',
      'light',
      'output',
      'settings',
      'transfer_function',
      'type',
      'v',
    ]);
    socket().ackSet();
    await flush();
    expect(restored).toEqual(['reopened']);
    expect(connection.session?.session).toBe('new-session');
    expect(connection.session?.state.settings.mode).toBe('sbrc_cone');
  });

  /** An owner with a set acknowledged, whose connection is lost and back: what it sent first. */
  async function ownerReconnected(session = 'mine') {
    const context = setup();
    const { clock, socket, connection } = context;
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', { ...OPENED, session });
    expect((await opened).ownerToken).toBe(OWNER_TOKEN);
    const set = connection.set({ settings: { mode: 'sbrc_cone' } });
    socket().ackSet();
    await set;
    const restored: (string | false)[] = [];
    connection.on('session', (info, r) => restored.push(r && `${r} ${info.session}`));
    socket().fail();
    clock.advance(100);
    socket().open();
    return { ...context, restored };
  }

  it('an owner resumes its own session after a lost connection, so its viewers keep watching', async () => {
    const { socket, connection, restored } = await ownerReconnected('mine');
    expect(OWNER_TOKEN).toMatch(/^[0-9a-f]{32}$/);
    expect(socket().sent).toEqual([
      {
        v: 1,
        id: expect.any(Number) as number,
        type: 'resume',
        session: 'mine',
        owner_token: OWNER_TOKEN,
        volume: 'ch2.nii.gz', // so that another server of a cluster can re-create it
      },
    ]);
    expect(connection.restoring).toBe(true);
    // The server's state wins: a set may have reached it whose ack was lost.
    const state = structuredClone(OPENED['state']) as State;
    state.settings.mode = 'dvr';
    socket().reply('opened', { ...OPENED, session: 'mine', state });
    await flush();
    expect(restored).toEqual(['resumed mine']);
    expect(socket().sent).toHaveLength(1); // no open, no state sent back
    expect(connection.restoring).toBe(false);
    expect(connection.session).toMatchObject({
      role: 'owner',
      session: 'mine',
      ownerToken: OWNER_TOKEN,
    });
    expect(connection.session?.state.settings.mode).toBe('dvr');
    // It is the owner: it may set again.
    const set = connection.set({ camera: { fov: 40 } });
    expect(socket().sent[1]).toMatchObject({ type: 'set', camera: { fov: 40 } });
    socket().ackSet();
    await set;
    expect(connection.session?.state.camera.fov).toBe(40);
  });

  it.each([
    ['the session ended', 'unknown_session', '/session'],
    ['another connection owns it', 'session_owned', '/session'],
    ['the token is wrong', 'invalid_value', '/owner_token'],
    ['the server has no resume', 'unknown_type', '/type'],
  ])(
    'an owner whose resume is refused (%s) opens a new session with its state',
    async (_, code, field) => {
      const { clock, socket, connection, restored } = await ownerReconnected('mine');
      const problems: string[] = [];
      connection.on('problem', (p) => problems.push(p));
      socket().reply('error', { code, field, message: 'refused' });
      await flush();
      expect(socket().sent[1]).toMatchObject({ type: 'open', volume: 'ch2.nii.gz' });
      socket().reply('opened', { ...OPENED, session: 'new-session', owner_token: 'ab'.repeat(16) });
      await flush();
      expect(socket().sent[2]).toMatchObject({ type: 'set', settings: { mode: 'sbrc_cone' } });
      socket().ackSet();
      await flush();
      expect(restored).toEqual(['reopened new-session']);
      expect(problems).toEqual([]);
      expect(connection.session).toMatchObject({
        session: 'new-session',
        ownerToken: 'ab'.repeat(16),
      });
      // The next reconnect resumes the new session, with its token.
      socket().fail();
      clock.advance(100);
      socket().open();
      expect(socket().sent[0]).toMatchObject({
        type: 'resume',
        session: 'new-session',
        owner_token: 'ab'.repeat(16),
      });
    },
  );

  it('a connection lost again during resume opens nothing and resumes on the next', async () => {
    const { clock, socket, connection, restored } = await ownerReconnected('mine');
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    socket().fail();
    await flush();
    expect(socket().sent).toHaveLength(1);
    expect(problems[0]).toMatch(/could not restore.*resume/);
    clock.advance(200);
    socket().open();
    expect(socket().sent[0]).toMatchObject({
      type: 'resume',
      session: 'mine',
      owner_token: OWNER_TOKEN,
    });
    socket().reply('opened', { ...OPENED, session: 'mine' });
    await flush();
    expect(restored).toEqual(['resumed mine']);
  });

  it('a viewer never holds an owner token, and leaving forgets it', async () => {
    const { clock, socket, connection } = setup();
    socket().open();
    const joined = connection.join('abc');
    socket().reply('joined', { ...OPENED_WITHOUT_TOKEN, type: 'joined', session: 'abc' });
    expect((await joined).ownerToken).toBeUndefined();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const left = connection.leave();
    socket().reply('ack', { of: 'close' });
    await left;
    socket().fail();
    clock.advance(100);
    socket().open();
    expect(socket().sent).toEqual([]);
  });

  it('a viewer re-joins the session after a lost connection', async () => {
    const { clock, socket, connection } = setup();
    socket().open();
    const joined = connection.join('abc');
    expect(socket().sent[0]).toEqual({ v: 1, id: 1, type: 'join', session: 'abc' });
    socket().reply('joined', { ...OPENED, session: 'abc' });
    expect((await joined).role).toBe('viewer');
    socket().fail();
    clock.advance(100);
    socket().open();
    expect(socket().sent[0]).toMatchObject({ type: 'join', session: 'abc' });
  });

  it('says so when the session cannot be restored', async () => {
    const { clock, socket, connection } = setup();
    socket().open();
    const joined = connection.join('abc');
    socket().reply('joined', { ...OPENED, session: 'abc' });
    await joined;
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    socket().fail();
    clock.advance(100);
    socket().open();
    socket().reply('error', { code: 'rate_limited', field: '/', message: 'too many requests' });
    await flush();
    expect(problems[0]).toMatch(/could not restore.*rate_limited/);
  });

  it('times out a request without an answer, and refuses to send while disconnected', async () => {
    const { clock, socket, connection } = setup();
    expect(() => connection.render(false)).toThrow(RequestFailed);
    socket().open();
    const stats = connection.stats();
    clock.advance(1000);
    expect(await stats.catch((e: unknown) => (e as Error).message)).toMatch(/no answer/);
  });

  it('ignores what it cannot read and says so', () => {
    const { socket, connection } = setup();
    socket().open();
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    socket().receive('not json');
    socket().receive(new Uint8Array([1, 2, 3]).buffer as ArrayBuffer);
    socket().receive('{"v":1,"type":"state","session":"s"}');
    expect(problems).toHaveLength(3);
    // A type a newer server added within v1 is no problem (§3).
    socket().receive('{"v":1,"type":"announcement","text":"hi"}');
    expect(problems).toHaveLength(3);
  });

  it('names the volume, the joined session and the access token in the WebSocket URL', () => {
    expect(routedUrl('wss://h:8443/ws', { volume: 'a b.nii.gz', session: 's1' }, 't+k')).toBe(
      'wss://h:8443/ws?volume=a+b.nii.gz&session=s1&token=t%2Bk',
    );
    expect(routedUrl('ws://h/ws?token=old&x=1', {})).toBe('ws://h/ws?x=1');
    const { socket } = setup({
      accessToken: 'secret',
      route: { volume: 'ch2.nii.gz', session: 'abc' },
    });
    expect(socket().url).toBe('ws://test/ws?volume=ch2.nii.gz&session=abc&token=secret');
  });

  it("opening another volume moves to a WebSocket routed to that volume's server", async () => {
    const { sockets, socket, statuses, connection } = setup({ accessToken: 'k', route: {} });
    socket().open();
    expect(socket().url).toBe('ws://test/ws?token=k');
    const opened = connection.open('ch2.nii.gz');
    expect(sockets).toHaveLength(2);
    expect(sockets[0]!.readyState).toBe(3);
    expect(socket().url).toBe('ws://test/ws?volume=ch2.nii.gz&token=k');
    expect(connection.moving).toBe(true);
    socket().open();
    await flush();
    expect(connection.moving).toBe(false);
    expect(socket().sent[0]).toMatchObject({ type: 'open', volume: 'ch2.nii.gz' });
    socket().reply('opened', OPENED);
    await opened;
    expect(statuses).not.toContain('lost'); // a move is no loss
    // The same volume again: the same WebSocket.
    const again = connection.open('ch2.nii.gz');
    expect(sockets).toHaveLength(2);
    socket().reply('opened', OPENED);
    await again;
  });

  it('an owner whose server died re-creates its session on another one and sends its state back', async () => {
    const { socket, connection, restored } = await ownerReconnected('mine');
    expect(socket().sent[0]).toMatchObject({
      type: 'resume',
      session: 'mine',
      volume: 'ch2.nii.gz',
    });
    socket().reply('opened', { ...OPENED, session: 'mine', recreated: true });
    await flush();
    expect(socket().sent[1]).toMatchObject({ type: 'set', settings: { mode: 'sbrc_cone' } });
    socket().ackSet();
    await flush();
    expect(restored).toEqual(['recreated mine']);
    expect(connection.session).toMatchObject({ session: 'mine', ownerToken: OWNER_TOKEN });
    expect(connection.session?.state.settings.mode).toBe('sbrc_cone');
  });

  /** A viewer of `abc` whose connection was lost and is back: the join it sent first. */
  async function viewerReconnected() {
    const context = setup({ followOwnerMs: 1000, followRetryMs: 250, route: {} });
    const { clock, socket, connection } = context;
    socket().open();
    const joined = connection.join('abc', 'ch2.nii.gz');
    await flush();
    expect(socket().url).toBe('ws://test/ws?volume=ch2.nii.gz&session=abc');
    socket().open();
    await flush();
    socket().reply('joined', { ...OPENED_WITHOUT_TOKEN, type: 'joined', session: 'abc' });
    await joined;
    const lost: string[] = [];
    const restored: (string | false)[] = [];
    connection.on('sessionLost', (session, outcome) => lost.push(`${outcome} ${session}`));
    connection.on('session', (_, r) => restored.push(r));
    socket().fail();
    clock.advance(100);
    socket().open();
    expect(socket().url).toBe('ws://test/ws?volume=ch2.nii.gz&session=abc');
    expect(socket().sent[0]).toMatchObject({ type: 'join', session: 'abc' });
    socket().reply('error', { code: 'unknown_session', field: '/session', message: 'no session' });
    await flush();
    return { ...context, lost, restored };
  }

  it('a viewer whose session died with its server follows the owner to where it re-opens it', async () => {
    const { clock, socket, lost, restored } = await viewerReconnected();
    expect(lost).toEqual(['waiting abc']);
    clock.advance(250);
    await flush();
    expect(socket().sent[1]).toMatchObject({ type: 'join', session: 'abc' });
    socket().reply('joined', { ...OPENED_WITHOUT_TOKEN, type: 'joined', session: 'abc' });
    await flush();
    expect(restored).toEqual(['rejoined']);
  });

  it('a viewer whose owner does not come back is told the session ended', async () => {
    const { clock, socket, connection, lost, restored } = await viewerReconnected();
    for (let attempt = 1; attempt <= 4; attempt++) {
      clock.advance(250);
      await flush();
      socket().reply('error', {
        code: 'unknown_session',
        field: '/session',
        message: 'no session',
      });
      await flush();
    }
    expect(socket().sent).toHaveLength(5);
    expect(lost).toEqual(['waiting abc', 'ended abc']);
    expect(restored).toEqual([]);
    expect(connection.restoring).toBe(false);
    clock.advance(10_000);
    expect(socket().sent).toHaveLength(5); // it stops asking
  });

  it('close() stops reconnecting', () => {
    const { clock, sockets, socket, statuses, connection } = setup();
    socket().open();
    connection.close();
    clock.advance(10_000);
    expect(sockets).toHaveLength(1);
    expect(statuses.slice(-1)).toEqual(['closed']);
  });
});

describe('Connection: label maps and picks', () => {
  /** An owner of `session` (with an owner token or not) that drew AAL. */
  async function ownerWithLabels(session = 'mine', token = true) {
    const context = setup();
    const { socket, connection } = context;
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', { ...(token ? OPENED : OPENED_WITHOUT_TOKEN), session });
    await opened;
    const told: string[] = [];
    connection.on('labels', (info) =>
      told.push(`${info.labels?.volume ?? 'none'} ${info.labels?.labels.length ?? 0}`),
    );
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    const adding = connection.addLabels('aal.nii.gz');
    expect(socket().sent.at(-1)).toMatchObject({ type: 'add_labels', volume: 'aal.nii.gz' });
    socket().reply('labels', { ...LABELS_ADDED, session });
    await adding;
    const set = connection.set({ labels: { only: [45, 46, 57] } });
    socket().reply('ack', { of: 'set', state: LABELLED_STATE });
    await set;
    return { ...context, told, problems };
  }

  it('an owner draws a label map and removes it; the mirror takes what the server answers', async () => {
    const { socket, connection, told } = await ownerWithLabels();
    expect(connection.session?.labels?.volume).toBe('aal.nii.gz');
    expect(connection.session?.labels?.labels).toHaveLength(116);
    expect(connection.session?.state.labels?.blend).toBe(0.8);
    const removing = connection.removeLabels();
    expect(socket().sent.at(-1)).toMatchObject({ type: 'remove_labels' });
    socket().reply('labels', { ...LABELS_REMOVED, session: 'mine' });
    await removing;
    expect(connection.session?.labels).toBeUndefined();
    expect(connection.session?.state.labels).toBeUndefined();
    expect(told).toEqual(['aal.nii.gz 116', 'none 0']);
  });

  it('a label map the server refuses changes nothing', async () => {
    const { socket, connection } = setup();
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const adding = connection.addLabels('ch2bet.nii.gz');
    socket().reply('error', {
      code: 'volume_unreadable',
      field: '/volume',
      message: 'not a label map',
    });
    expect(await adding.catch((e: unknown) => e)).toBeInstanceOf(ServerError);
    expect(connection.session?.labels).toBeUndefined();
  });

  it('a viewer is told the labels after joined; the names stay while the map does', async () => {
    const { socket, connection } = setup();
    socket().open();
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    const told: number[] = [];
    connection.on('labels', (info) => told.push(info.labels?.labels.length ?? 0));
    const joined = connection.join('abc');
    socket().reply('joined', {
      ...OPENED_WITHOUT_TOKEN,
      type: 'joined',
      session: 'abc',
      state: LABELLED_STATE,
    });
    await joined;
    // A session this connection is not in: nothing of it.
    socket().receive(JSON.stringify({ v: 1, ...LABELS_AFTER_JOIN, session: 'other' }));
    socket().receive(JSON.stringify({ v: 1, ...LABELS_AFTER_JOIN, session: 'abc' }));
    expect(problems).toEqual([]);
    expect(told).toEqual([116]);
    expect(connection.session?.labels?.volume).toBe('aal.nii.gz');
    // The owner hides a label: the same map, still named.
    const hidden = structuredClone(LABELLED_STATE);
    hidden.labels!.styles['45']!.visible = false;
    socket().receive(JSON.stringify({ v: 1, type: 'state', session: 'abc', state: hidden }));
    expect(connection.session?.labels?.labels).toHaveLength(116);
    expect(connection.session?.state.labels?.styles['45']?.visible).toBe(false);
    // The owner draws another map: a viewer is sent its styles alone, which name nothing.
    const other = structuredClone(LABELLED_STATE);
    other.labels!.styles = { '1': other.labels!.styles['1']!, '2': other.labels!.styles['2']! };
    socket().receive(JSON.stringify({ v: 1, type: 'state', session: 'abc', state: other }));
    expect(connection.session?.labels).toBeUndefined();
    expect(Object.keys(connection.session?.state.labels?.styles ?? {})).toEqual(['1', '2']);
  });

  it('a viewer whose owner removes the map forgets its labels', async () => {
    const { socket, connection } = setup();
    socket().open();
    const joined = connection.join('abc');
    socket().reply('joined', { ...OPENED, type: 'joined', session: 'abc', state: LABELLED_STATE });
    await joined;
    socket().receive(JSON.stringify({ v: 1, ...LABELS_AFTER_JOIN, session: 'abc' }));
    socket().receive(
      JSON.stringify({ v: 1, type: 'state', session: 'abc', state: OPENED['state'] }),
    );
    expect(connection.session?.labels).toBeUndefined();
  });

  it('exports a still: the first status answers, the rest are events, the last its download', async () => {
    const { socket, connection } = setup({ accessToken: 'a+b' });
    socket().open();
    const opened = connection.open('ch2.nii.gz');
    socket().reply('opened', OPENED);
    await opened;
    const told: string[] = [];
    connection.on('exportStatus', (s) => told.push(`${s.state} ${s.progress}`));
    const problems: string[] = [];
    connection.on('problem', (p) => problems.push(p));
    const status = {
      export: '5f0c2a9e41d37b88c6e2f01a9b4d7e63',
      state: 'running',
      progress: 0,
      width: 300,
      height: 200,
      tiles: 0,
    };
    const exporting = connection.exportStill(300, 200);
    const request = socket().sent.at(-1)!;
    expect(request).toMatchObject({ type: 'export', width: 300, height: 200 });
    expect(checkClientMessage(request, recordedTerms)).toBeNull();
    socket().reply('export_status', status);
    expect((await exporting).export).toBe(status.export);
    const later = (extra: Record<string, unknown>) =>
      socket().receive(
        JSON.stringify({ v: 1, type: 'export_status', id: request['id'], ...status, ...extra }),
      );
    later({ progress: 0.5, tiles: 2 });
    connection.cancelExport(status.export);
    expect(socket().sent.at(-1)).toMatchObject({ type: 'cancel_export', export: status.export });
    expect(checkClientMessage(socket().sent.at(-1)!, recordedTerms)).toBeNull();
    later({ state: 'done', progress: 1, tiles: 2, url: `/exports/${status.export}`, bytes: 9 });
    expect(told).toEqual(['running 0.5', 'done 1']);
    expect(problems).toEqual([]);
    const url = new URL(
      connection.downloadUrl({
        v: 1,
        type: 'export_status',
        ...status,
        state: 'done',
        url: `/exports/${status.export}`,
      })!,
    );
    expect(url.origin).toBe('http://test');
    expect(url.pathname).toBe(`/exports/${status.export}`);
    expect(url.searchParams.get('volume')).toBe('ch2.nii.gz');
    expect(url.searchParams.get('token')).toBe('a+b');
  });

  it('any viewer picks a point of the view, answered by picked', async () => {
    const { socket, connection } = setup();
    socket().open();
    const joined = connection.join('abc');
    socket().reply('joined', { ...OPENED_WITHOUT_TOKEN, type: 'joined', session: 'abc' });
    await joined;
    const picking = connection.pick(0.55, 0.4);
    expect(socket().sent.at(-1)).toMatchObject({ type: 'pick', x: 0.55, y: 0.4 });
    socket().reply('picked', { ...PICKED_HIT, session: 'abc' });
    expect(await picking).toMatchObject({
      hit: true,
      label: { id: 19, name: 'Supp_Motor_Area_L' },
    });
  });

  it('after a lost connection the owner draws its map again before it sends its styles back (no owner token)', async () => {
    const { clock, socket, connection, told, problems } = await ownerWithLabels('mine', false);
    const restored: (string | false)[] = [];
    connection.on('session', (_, r) => restored.push(r));
    socket().fail();
    clock.advance(100);
    socket().open();
    expect(socket().sent[0]).toMatchObject({ type: 'open', volume: 'ch2.nii.gz' });
    socket().reply('opened', { ...OPENED, session: 'new-session' });
    await flush();
    // The server refuses labels while it draws no map: the map first.
    expect(socket().sent[1]).toMatchObject({ type: 'add_labels', volume: 'aal.nii.gz' });
    expect(socket().sent).toHaveLength(2);
    socket().reply('labels', { ...LABELS_ADDED, session: 'new-session' });
    await flush();
    const restore = socket().sent[2]!;
    expect(restore).toMatchObject({
      type: 'set',
      labels: { only: [45, 46, 57], styles: { '46': { opacity: 0.5 } }, blend: 0.8 },
    });
    socket().reply('ack', { of: 'set', state: LABELLED_STATE });
    await flush();
    expect(restored).toEqual(['reopened']);
    expect(problems).toEqual([]);
    expect(connection.session?.session).toBe('new-session');
    expect(connection.session?.labels?.labels).toHaveLength(116);
    expect(connection.session?.state.labels).toEqual(LABELLED_STATE.labels);
    expect(told).toEqual(['aal.nii.gz 116']);
  });

  it('a map that cannot be drawn again is said, and the rest of the state goes back', async () => {
    const { clock, socket, connection, problems } = await ownerWithLabels('mine', false);
    socket().fail();
    clock.advance(100);
    socket().open();
    socket().reply('opened', { ...OPENED, session: 'new-session' });
    await flush();
    socket().reply('error', {
      code: 'unknown_volume',
      field: '/volume',
      message: 'no such volume',
    });
    await flush();
    const restore = socket().sent[2]!;
    expect(restore['type']).toBe('set');
    expect(restore['labels']).toBeUndefined();
    expect(problems).toEqual([
      expect.stringMatching(/aal\.nii\.gz could not be drawn again: unknown_volume/) as string,
    ]);
    const unlabelled = structuredClone(LABELLED_STATE);
    delete unlabelled.labels;
    socket().reply('ack', { of: 'set', state: unlabelled });
    await flush();
    expect(connection.session?.labels).toBeUndefined();
    expect(connection.session?.state.labels).toBeUndefined();
  });

  it("a resumed owner's session still draws its map: nothing is sent again, the names follow", async () => {
    const { clock, socket, connection, told } = await ownerWithLabels('mine');
    socket().fail();
    clock.advance(100);
    socket().open();
    expect(socket().sent[0]).toMatchObject({ type: 'resume', session: 'mine' });
    socket().reply('opened', { ...OPENED, session: 'mine', state: LABELLED_STATE });
    await flush();
    // Known from before, until the server says them again.
    expect(connection.session?.labels?.labels).toHaveLength(116);
    socket().receive(JSON.stringify({ v: 1, ...LABELS_AFTER_JOIN, session: 'mine' }));
    expect(socket().sent).toHaveLength(1);
    expect(told).toEqual(['aal.nii.gz 116', 'aal.nii.gz 116']);
    expect(connection.session?.state.labels).toEqual((LABELS_AFTER_JOIN!['state'] as State).labels);
  });

  it('an owner whose server died re-creates its session, its label map drawn again first', async () => {
    const { clock, socket, connection } = await ownerWithLabels('mine');
    socket().fail();
    clock.advance(100);
    socket().open();
    socket().reply('opened', { ...OPENED, session: 'mine', recreated: true });
    await flush();
    expect(socket().sent[1]).toMatchObject({ type: 'add_labels', volume: 'aal.nii.gz' });
    socket().reply('labels', { ...LABELS_ADDED, session: 'mine' });
    await flush();
    expect(socket().sent[2]).toMatchObject({ type: 'set', labels: { only: [45, 46, 57] } });
    socket().reply('ack', { of: 'set', state: LABELLED_STATE });
    await flush();
    expect(connection.session?.labels?.volume).toBe('aal.nii.gz');
    expect(connection.session?.state.labels?.blend).toBe(0.8);
  });
});
