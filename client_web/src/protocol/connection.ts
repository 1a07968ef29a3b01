// The protocol in one object: the WebSocket, `hello`, requests matched to answers by id, frames,
// server errors, and reconnect with session restore (resume the owned session with its owner
// token, else re-open the volume and send the state back; or re-join a shared session). The
// WebSocket URL names the volume (and the session joined), which a cluster's proxy routes by
// (proto/README.md §1): opening another volume moves to a new WebSocket. A label map the session
// draws is restored before its styles: the server refuses them while it draws none. No DOM: the
// socket comes from a factory so tests can pass a fake.

import { parseFrame, type Frame } from './frame_header';
import {
  ANSWERS,
  answersOlderRenders,
  encodeClientMessage,
  parseServerMessage,
  restorePatch,
  UnknownMessageType,
  type AnswerTo,
  type ClientMessage,
  type ClientRequest,
  type ErrorMessage,
  type ExportStatusMessage,
  type HelloMessage,
  type LabelsMessage,
  type LabelsState,
  type LabelSummary,
  type Listing,
  type OpenedMessage,
  type PickedMessage,
  type ServerMessage,
  type State,
  type StateMessage,
  type StatePatch,
  type VolumeSummary,
} from './messages';

/** The part of a browser WebSocket this client uses. */
export interface SocketLike {
  binaryType: string;
  readonly readyState: number;
  onopen: ((event: unknown) => void) | null;
  onclose: ((event: { code: number; reason: string; wasClean?: boolean }) => void) | null;
  onerror: ((event: unknown) => void) | null;
  onmessage: ((event: { data: unknown }) => void) | null;
  send(data: string): void;
  close(code?: number, reason?: string): void;
}

export type SocketFactory = (url: string) => SocketLike;

/** What the WebSocket URL names, for a cluster's proxy to route by. */
export interface Route {
  volume?: string;
  session?: string;
}

/**
 * `base` with the route and the access token as query parameters:
 * ws://host/ws?volume=ch2.nii.gz&session=…&token=…
 */
export function routedUrl(base: string, route: Route, token?: string): string {
  const url = new URL(base);
  for (const key of ['volume', 'session', 'token']) url.searchParams.delete(key);
  if (route.volume !== undefined) url.searchParams.set('volume', route.volume);
  if (route.session !== undefined) url.searchParams.set('session', route.session);
  if (token !== undefined && token !== '') url.searchParams.set('token', token);
  return url.toString();
}

const OPEN = 1;

export type ConnectionStatus =
  | { kind: 'connecting'; attempt: number }
  | { kind: 'connected'; hello: HelloMessage }
  /** The connection was up and went away; retrying. */
  | { kind: 'lost'; attempt: number; retryInMs: number; reason: string }
  /** The server could not be reached (yet); retrying. */
  | { kind: 'unreachable'; attempt: number; retryInMs: number; reason: string }
  | { kind: 'closed' };

/** An `error` from the server, with the request it answers when known. */
export class ServerError extends Error {
  readonly code: string;
  readonly field: string;
  readonly id: number | undefined;
  readonly requestType: string | undefined;

  constructor(message: ErrorMessage, requestType?: string) {
    super(message.message);
    this.name = 'ServerError';
    this.code = message.code;
    this.field = message.field;
    this.id = message.id;
    this.requestType = requestType;
  }

  /** "out_of_range at /settings/size/0: must be within 1..2048" */
  describe(): string {
    const where = this.field && this.field !== '/' ? ` at ${this.field}` : '';
    const what = this.requestType ? ` (${this.requestType})` : '';
    return `${this.code}${where}${what}: ${this.message}`;
  }
}

/** A request that got no answer: the connection went away or it timed out. */
export class RequestFailed extends Error {
  constructor(message: string) {
    super(message);
    this.name = 'RequestFailed';
  }
}

export type Role = 'none' | 'owner' | 'viewer';

/** The label map a session draws: its id in `volumes` and its labels as `labels` listed them. */
export interface DrawnLabels {
  volume: string;
  labels: LabelSummary[];
}

export interface SessionInfo {
  role: Role;
  session: string;
  volume: VolumeSummary;
  histogram: number[];
  state: State;
  /** An owner's secret for `resume` (absent for viewers, and from servers older than resume). */
  ownerToken?: string;
  /**
   * The label map drawn, as the last `labels` told; absent while none is drawn. The server tells
   * every viewer as the owner adds or removes a map; one older than that told a viewer only as it
   * joined, so its state could style ids it has no names for.
   */
  labels?: DrawnLabels;
}

/**
 * How a session came back after a reconnect: the owner's own session again (`resumed`; its viewers
 * stayed), the same session re-created on another server of the cluster with the saved state
 * (`recreated`; its viewers follow), a new session on the same volume with the saved state
 * (`reopened`), or the shared session joined again (`rejoined`).
 */
export type Restored = 'resumed' | 'recreated' | 'reopened' | 'rejoined';

export interface ConnectionEvents {
  status: (status: ConnectionStatus) => void;
  /** `opened`/`joined`, also after a reconnect (`restored` says how; false before any). */
  session: (info: SessionInfo, restored: Restored | false) => void;
  /** A viewer's session got a new state (`info.state`): its owner changed it. */
  state: (info: SessionInfo) => void;
  /**
   * The session's label map changed (`info.labels`, with `info.state`): drawn or removed (by this
   * owner, or by the owner a viewer watches), or told after a join or a resume.
   */
  labels: (info: SessionInfo) => void;
  frame: (frame: Frame) => void;
  /** An error not answered to a pending request: a failed render, or one without id. */
  serverError: (error: ServerError) => void;
  /** Something the server sent that this client cannot read, or a failed restore. */
  problem: (message: string) => void;
  /** A render request was sent (id, interactive). */
  renderSent: (id: number, interactive: boolean) => void;
  /**
   * A render of this connection was answered by an error instead of a frame (`too_much_work`,
   * `render_failed`, `rate_limited`, `no_session`: the server sends the render's id with it);
   * answersOlderRenders says whether it answers the older renders too. `serverError` reports the
   * error too.
   */
  renderFailed: (id: number, error: ServerError) => void;
  /**
   * A viewer's session is gone from the server it reconnected to (its server died): it waits for
   * the owner to re-open it (`waiting`), or gave up after `followOwnerMs` (`ended`).
   */
  sessionLost: (session: string, outcome: 'waiting' | 'ended') => void;
  /** An export of this connection went on or ended (its first status answers `exportStill`). */
  exportStatus: (status: ExportStatusMessage) => void;
}

export interface ConnectionOptions {
  createSocket?: SocketFactory;
  /** Waits before reconnect attempts 1, 2, ...; the last repeats. */
  reconnectDelaysMs?: number[];
  requestTimeoutMs?: number;
  setTimer?: (callback: () => void, ms: number) => unknown;
  clearTimer?: (handle: unknown) => void;
  /** The access token the server asks for on the WebSocket upgrade (`?token=`). */
  accessToken?: string;
  /** What the first WebSocket URL names (the page's volume or join link). */
  route?: Route;
  /** How long a viewer whose session vanished waits for its owner to re-open it. */
  followOwnerMs?: number;
  /** The wait between its attempts to join again. */
  followRetryMs?: number;
}

interface Pending {
  type: ClientRequest['type'];
  resolve: (message: ServerMessage) => void;
  reject: (error: Error) => void;
  timer: unknown;
}

/** The session a connection is in, as a reconnect restores it. */
type Wanted =
  | { role: 'owner'; volume: string; session: string; ownerToken?: string }
  | { role: 'viewer'; session: string; volume?: string };

type Listeners = { [K in keyof ConnectionEvents]: ConnectionEvents[K][] };

export class Connection {
  private socket: SocketLike | null = null;
  private nextId = 1;
  private pending = new Map<number, Pending>();
  private renderIds = new Set<number>();
  private listeners: Listeners = {
    status: [],
    session: [],
    state: [],
    labels: [],
    frame: [],
    serverError: [],
    problem: [],
    renderSent: [],
    renderFailed: [],
    sessionLost: [],
    exportStatus: [],
  };
  private attempt = 0;
  private everConnected = false;
  private reconnectTimer: unknown = null;
  private stopped = false;
  private readonly options: Required<Omit<ConnectionOptions, 'accessToken' | 'route'>> &
    Pick<ConnectionOptions, 'accessToken'>;
  /** What the current (or next) WebSocket URL names. */
  private route: Route;
  /** Waits for the hello of a WebSocket opened for another volume. */
  private moved: { resolve: () => void; reject: (e: Error) => void } | null = null;

  hello: HelloMessage | null = null;
  /** True while a reconnect re-opens or re-joins the session (nothing else should be sent). */
  restoring = false;
  status: ConnectionStatus = { kind: 'closed' };
  session: SessionInfo | null = null;
  /** What to restore after a reconnect; kept while the connection is down. */
  private wanted: Wanted | null = null;

  constructor(
    readonly url: string,
    options: ConnectionOptions = {},
  ) {
    this.options = {
      createSocket:
        options.createSocket ?? ((u: string) => new WebSocket(u) as unknown as SocketLike),
      reconnectDelaysMs: options.reconnectDelaysMs ?? [500, 1000, 2000, 4000, 8000],
      requestTimeoutMs: options.requestTimeoutMs ?? 30000,
      setTimer: options.setTimer ?? ((cb, ms) => setTimeout(cb, ms)),
      clearTimer: options.clearTimer ?? ((h) => clearTimeout(h as ReturnType<typeof setTimeout>)),
      accessToken: options.accessToken,
      followOwnerMs: options.followOwnerMs ?? 15000,
      followRetryMs: options.followRetryMs ?? 500,
    };
    this.route = { ...options.route };
  }

  /** The URL the next WebSocket opens. */
  get socketUrl(): string {
    return routedUrl(this.url, this.route, this.options.accessToken);
  }

  /** True while the connection moves to a WebSocket for another volume. */
  get moving(): boolean {
    return this.moved !== null;
  }

  on<K extends keyof ConnectionEvents>(event: K, listener: ConnectionEvents[K]): void {
    this.listeners[event].push(listener);
  }

  private emit<K extends keyof ConnectionEvents>(
    event: K,
    ...args: Parameters<ConnectionEvents[K]>
  ): void {
    for (const l of this.listeners[event]) {
      (l as (...a: Parameters<ConnectionEvents[K]>) => void)(...args);
    }
  }

  private setStatus(status: ConnectionStatus): void {
    this.status = status;
    this.emit('status', status);
  }

  get connected(): boolean {
    return this.status.kind === 'connected';
  }

  /** Opens the WebSocket; reconnects by itself until close(). */
  connect(): void {
    this.stopped = false;
    this.openSocket();
  }

  private openSocket(): void {
    this.reconnectTimer = null;
    this.attempt += 1;
    this.setStatus({ kind: 'connecting', attempt: this.attempt });
    let socket: SocketLike;
    const url = this.socketUrl;
    try {
      socket = this.options.createSocket(url);
    } catch (e) {
      this.scheduleReconnect(`cannot open ${url}: ${String(e)}`);
      return;
    }
    socket.binaryType = 'arraybuffer';
    this.socket = socket;
    let gotHello = false;
    socket.onmessage = (event) => {
      if (this.socket !== socket) return;
      if (typeof event.data === 'string') {
        let message: ServerMessage;
        try {
          message = parseServerMessage(event.data);
        } catch (e) {
          // A newer server may send types this client does not know (§3): nothing to do for them.
          if (!(e instanceof UnknownMessageType)) {
            this.emit('problem', `unreadable message from the server: ${String(e)}`);
          }
          return;
        }
        if (message.type === 'hello') {
          gotHello = true;
          this.onHello(message);
        } else {
          this.onMessage(message);
        }
      } else if (event.data instanceof ArrayBuffer) {
        let frame: Frame;
        try {
          frame = parseFrame(event.data);
        } catch (e) {
          this.emit('problem', `unreadable frame: ${String(e)}`);
          return;
        }
        this.renderIds.forEach((id) => {
          if (id <= frame.header.request) this.renderIds.delete(id);
        });
        this.emit('frame', frame);
      }
    };
    socket.onerror = () => {
      // The close event that follows says what happened.
    };
    socket.onclose = (event) => {
      if (this.socket !== socket) return;
      this.socket = null;
      this.failPending('the connection was lost');
      if (this.stopped) {
        this.setStatus({ kind: 'closed' });
        return;
      }
      const reason = event.reason || `WebSocket closed (code ${event.code})`;
      this.scheduleReconnect(reason, gotHello);
    };
  }

  private scheduleReconnect(reason: string, wasUp = false): void {
    const delays = this.options.reconnectDelaysMs;
    const retryInMs = delays[Math.max(0, Math.min(this.attempt - 1, delays.length - 1))] ?? 1000;
    this.setStatus({
      kind: wasUp || this.everConnected ? 'lost' : 'unreachable',
      attempt: this.attempt,
      retryInMs,
      reason,
    });
    this.reconnectTimer = this.options.setTimer(() => this.openSocket(), retryInMs);
  }

  /** Reconnects now instead of waiting for the next attempt. */
  retryNow(): void {
    if (this.reconnectTimer !== null) {
      this.options.clearTimer(this.reconnectTimer);
      this.openSocket();
    }
  }

  /**
   * Routes the WebSocket to `route`'s volume: a cluster's proxy sends each volume to one server,
   * so another volume means another WebSocket, whose hello the returned promise waits for (null:
   * this one serves). The session of the old one is left with it.
   */
  private routeTo(route: Route): Promise<void> | null {
    const sameServer = route.volume === this.route.volume;
    this.route = route;
    if (sameServer || !this.socket) return null;
    const old = this.socket;
    this.socket = null; // its close is no loss to report
    this.wanted = null;
    this.failPending('the connection moved to another volume');
    old.close(1000, 'another volume');
    return new Promise<void>((resolve, reject) => {
      this.moved = { resolve, reject };
      this.openSocket();
    });
  }

  /** Closes for good (no reconnect). */
  close(): void {
    this.moved?.reject(new RequestFailed('the connection was closed'));
    this.moved = null;
    this.stopped = true;
    if (this.reconnectTimer !== null) {
      this.options.clearTimer(this.reconnectTimer);
      this.reconnectTimer = null;
    }
    if (this.socket) {
      this.socket.close(1000, 'client closed');
    } else {
      this.setStatus({ kind: 'closed' });
    }
  }

  /** Drops the socket as if the network failed (tests, and the "reconnect" button). */
  dropForTesting(): void {
    this.socket?.close(4000, 'dropped by the client');
  }

  private onHello(hello: HelloMessage): void {
    const restoring = this.everConnected && this.wanted !== null;
    this.hello = hello;
    this.attempt = 0;
    this.everConnected = true;
    this.setStatus({ kind: 'connected', hello });
    const moved = this.moved;
    this.moved = null;
    moved?.resolve();
    if (restoring) {
      void this.restore();
    }
  }

  private sleep(ms: number): Promise<void> {
    return new Promise((resolve) => this.options.setTimer(resolve, ms));
  }

  private async restore(): Promise<void> {
    const wanted = this.wanted;
    const previous = this.session;
    if (!wanted) return;
    this.restoring = true;
    try {
      if (wanted.role === 'owner') {
        const resumed =
          wanted.ownerToken === undefined
            ? null
            : await this.resume(wanted.session, wanted.ownerToken, wanted.volume);
        if (resumed && resumed.recreated && previous) {
          // Another server of the cluster re-created the session with the default state: ours
          // goes back, and its viewers, who join the same id, follow.
          await this.sendStateBack(previous, resumed.info);
          this.session = resumed.info;
          this.restoring = false;
          this.emit('session', resumed.info, 'recreated');
          return;
        }
        if (resumed) {
          // The session's state is the server's: it may hold a set whose ack was lost. Its label
          // map's names follow the opened (a labels without id); until then they are those known.
          const styles = resumed.info.state.labels?.styles;
          if (previous?.labels && styles && namesTheLabels(previous.labels.labels, styles)) {
            resumed.info.labels = previous.labels;
          }
          this.session = resumed.info;
          this.restoring = false;
          this.emit('session', resumed.info, 'resumed');
          return;
        }
        const opened = await this.request({ type: 'open', volume: wanted.volume });
        const info = this.sessionFrom(opened, 'owner');
        this.wanted = this.ownerWanted(wanted.volume, info);
        if (previous) await this.sendStateBack(previous, info);
        this.session = info;
        this.restoring = false;
        this.emit('session', info, 'reopened');
      } else {
        const joined = await this.rejoin(wanted.session);
        if (!joined) return;
        this.session = this.sessionFrom(joined, 'viewer');
        this.restoring = false;
        this.emit('session', this.session, 'rejoined');
      }
    } catch (e) {
      const text = e instanceof ServerError ? e.describe() : String(e);
      this.emit('problem', `could not restore the session after reconnecting: ${text}`);
    } finally {
      this.restoring = false;
    }
  }

  /**
   * Sends the state of `previous` back to the session `info` (re-opened or re-created with the
   * default state): its label map drawn again first, then the whole state, its labels' styles as
   * what differs from the map's own. A map that cannot be drawn again is said and left out. The
   * mirror becomes the state the server answers with.
   */
  private async sendStateBack(previous: SessionInfo, info: SessionInfo): Promise<void> {
    let drawn: LabelsState | undefined;
    const map = previous.labels?.volume;
    if (map && previous.state.labels) {
      try {
        const answer = await this.request({ type: 'add_labels', volume: map });
        info.labels = { volume: answer.volume, labels: answer.labels };
        info.state = answer.state;
        drawn = answer.state.labels;
      } catch (e) {
        if (!(e instanceof ServerError)) throw e;
        this.emit('problem', `the label map ${map} could not be drawn again: ${e.describe()}`);
      }
    }
    const ack = await this.request({ type: 'set', ...restorePatch(previous.state, drawn) });
    if (ack.state) {
      info.state = ack.state;
    } else {
      const { labels, ...rest } = structuredClone(previous.state);
      info.state = drawn && labels ? { ...rest, labels } : rest;
    }
  }

  /**
   * Becomes the owner of `session` again, so that its viewers keep watching; the volume lets a
   * server of the cluster re-create the session when the one that held it is gone. Resolves null
   * when the server refuses (the session ended, another connection owns it, a server without
   * resume): the caller opens a new session instead. A lost connection rejects, to be retried on
   * the next.
   */
  private async resume(
    session: string,
    ownerToken: string,
    volume: string,
  ): Promise<{ info: SessionInfo; recreated: boolean } | null> {
    try {
      const opened = await this.request({
        type: 'resume',
        session,
        owner_token: ownerToken,
        volume,
      });
      return { info: this.sessionFrom(opened, 'owner'), recreated: opened.recreated === true };
    } catch (e) {
      if (e instanceof ServerError) return null;
      throw e;
    }
  }

  /**
   * Joins `session` again after a reconnect. When the server does not have it (the one that held
   * it died), its owner may re-create it here in a moment: joins again until `followOwnerMs` has
   * passed, then says the session ended and resolves null.
   */
  private async rejoin(session: string): Promise<OpenedMessage | null> {
    const socket = this.socket;
    let waitedMs = 0;
    for (;;) {
      try {
        return await this.request({ type: 'join', session });
      } catch (e) {
        if (!(e instanceof ServerError) || e.code !== 'unknown_session') throw e;
        if (waitedMs >= this.options.followOwnerMs) {
          this.wanted = null;
          this.emit('sessionLost', session, 'ended');
          return null;
        }
        if (waitedMs === 0) this.emit('sessionLost', session, 'waiting');
      }
      await this.sleep(this.options.followRetryMs);
      waitedMs += this.options.followRetryMs;
      if (this.socket !== socket) throw new RequestFailed('join: the connection was lost');
    }
  }

  private ownerWanted(volume: string, info: SessionInfo): Wanted {
    return { role: 'owner', volume, session: info.session, ownerToken: info.ownerToken };
  }

  private onMessage(message: ServerMessage): void {
    if (message.type === 'state') {
      this.onState(message);
      return;
    }
    if (message.type === 'labels' && message.id === undefined) {
      this.onLabels(message);
      return;
    }
    const id = 'id' in message ? message.id : undefined;
    const pending = id !== undefined ? this.pending.get(id) : undefined;
    if (pending && id !== undefined) {
      this.pending.delete(id);
      this.options.clearTimer(pending.timer);
      const answers: readonly string[] = ANSWERS[pending.type];
      if (message.type === 'error') {
        pending.reject(new ServerError(message, pending.type));
      } else if (answers.includes(message.type)) {
        pending.resolve(message);
      } else {
        pending.reject(new RequestFailed(`${pending.type} answered by ${message.type}`));
      }
      return;
    }
    if (message.type === 'export_status') {
      this.emit('exportStatus', message);
      return;
    }
    if (message.type === 'error') {
      const render = id !== undefined && this.renderIds.has(id) ? id : undefined;
      const error = new ServerError(message, render !== undefined ? 'render' : undefined);
      if (render !== undefined) {
        if (answersOlderRenders(error.code)) {
          this.renderIds.forEach((r) => {
            if (r <= render) this.renderIds.delete(r);
          });
        } else {
          this.renderIds.delete(render);
        }
        this.emit('renderFailed', render, error);
      }
      this.emit('serverError', error);
      return;
    }
    this.emit('problem', `unexpected ${message.type} from the server`);
  }

  /** The owner changed the session this connection watches: the mirror takes the new state. */
  private onState(message: StateMessage): void {
    const session = this.session;
    // A session this connection has left may still have had a state on its way; and an owner's
    // mirror follows its own acknowledged sets (the server sends owners no state).
    if (!session || session.role !== 'viewer' || session.session !== message.session) return;
    session.state = message.state;
    // A map drawn or replaced comes as `labels` before any state styling it; a state styling
    // other ids than the names known (an older server, which named them only as a viewer joined)
    // leaves the labels by id.
    const styles = message.state.labels?.styles;
    if (!styles || (session.labels && !namesTheLabels(session.labels.labels, styles))) {
      delete session.labels;
    }
    this.emit('state', session);
  }

  /**
   * The labels of the session this connection is in: told after a join or a resume, and to a
   * viewer as its owner adds or removes a map.
   */
  private onLabels(message: LabelsMessage): void {
    const session = this.session;
    if (!session || session.session !== message.session) return;
    this.takeLabels(session, message);
  }

  private takeLabels(session: SessionInfo, message: LabelsMessage): void {
    session.state = message.state;
    if (message.volume === '') delete session.labels;
    else session.labels = { volume: message.volume, labels: message.labels };
    this.emit('labels', session);
  }

  private failPending(reason: string): void {
    const pending = [...this.pending.values()];
    this.pending.clear();
    this.renderIds.clear();
    for (const p of pending) {
      this.options.clearTimer(p.timer);
      p.reject(new RequestFailed(`${p.type}: ${reason}`));
    }
  }

  private sendMessage(message: ClientRequest): number {
    if (!this.socket || this.socket.readyState !== OPEN || !this.connected) {
      throw new RequestFailed(`${message.type}: not connected`);
    }
    const id = this.nextId++;
    this.socket.send(encodeClientMessage({ v: 1, id, ...message } as ClientMessage));
    return id;
  }

  /**
   * Sends a request and resolves with its answer (ANSWERS says which message that is); rejects with
   * ServerError or RequestFailed. Any request goes this way: a new message type needs its type, its
   * answer and its checks in messages.ts, and no method here.
   */
  request<R extends ClientRequest>(message: R): Promise<AnswerTo<R['type']>> {
    return new Promise<AnswerTo<R['type']>>((resolve, reject) => {
      let id: number;
      try {
        id = this.sendMessage(message);
      } catch (e) {
        reject(e as Error);
        return;
      }
      const timer = this.options.setTimer(() => {
        if (this.pending.delete(id)) {
          reject(
            new RequestFailed(`${message.type}: no answer in ${this.options.requestTimeoutMs} ms`),
          );
        }
      }, this.options.requestTimeoutMs);
      this.pending.set(id, {
        type: message.type,
        resolve: resolve as (m: ServerMessage) => void,
        reject,
        timer,
      });
    });
  }

  private sessionFrom(message: OpenedMessage, role: 'owner' | 'viewer'): SessionInfo {
    const info: SessionInfo = {
      role,
      session: message.session,
      volume: message.volume,
      histogram: message.histogram,
      state: message.state,
    };
    if (role === 'owner' && message.owner_token !== undefined)
      info.ownerToken = message.owner_token;
    return info;
  }

  /** The volumes the server lists, and whether its scan of its data folder is still under way. */
  async listVolumes(): Promise<{ volumes: VolumeSummary[]; listing: Listing }> {
    const { volumes, listing } = await this.request({ type: 'list_volumes' });
    return { volumes, listing };
  }

  /** Opens a volume in a new session this connection owns (on that volume's server). */
  open(volume: string): Promise<SessionInfo> {
    const moving = this.routeTo({ volume });
    return moving ? moving.then(() => this.openHere(volume)) : this.openHere(volume);
  }

  private async openHere(volume: string): Promise<SessionInfo> {
    const answer = await this.request({ type: 'open', volume });
    this.session = this.sessionFrom(answer, 'owner');
    this.wanted = this.ownerWanted(volume, this.session);
    this.emit('session', this.session, false);
    return this.session;
  }

  /**
   * Joins another connection's session as a viewer; `volume`, the session's (a share link names
   * it), routes the WebSocket to the server that holds the session.
   */
  join(session: string, volume?: string): Promise<SessionInfo> {
    const moving = this.routeTo({ volume: volume ?? this.route.volume, session });
    return moving ? moving.then(() => this.joinHere(session)) : this.joinHere(session);
  }

  private async joinHere(session: string): Promise<SessionInfo> {
    const answer = await this.request({ type: 'join', session });
    this.wanted = { role: 'viewer', session, volume: answer.volume.id };
    this.session = this.sessionFrom(answer, 'viewer');
    this.emit('session', this.session, false);
    return this.session;
  }

  /**
   * Patches the session's state (owner only); the mirror becomes the state the server answers
   * with, the patch as it applied it.
   */
  async set(patch: StatePatch): Promise<void> {
    const answer = await this.request({ type: 'set', ...patch });
    if (this.session && answer.state) {
      this.session.state = answer.state;
    }
  }

  /** Asks for a frame; it arrives through the `frame` event. Returns the request id. */
  render(interactive: boolean): number {
    const id = this.sendMessage({ type: 'render', interactive });
    this.renderIds.add(id);
    this.emit('renderSent', id, interactive);
    return id;
  }

  /**
   * Renders the session's view as a PNG still of width x height pixels on the server (in tiles,
   * at the lowest priority); resolves with its first status, the rest come as `exportStatus`
   * events, the last with the URL to download it from (downloadUrl).
   */
  exportStill(width: number, height: number): Promise<ExportStatusMessage> {
    return this.request({ type: 'export', width, height });
  }

  /**
   * Starts a movie of the session's view turning (`rock` 0: a whole turn, else rocking ±rock°),
   * `frames` frames of width x height (even): as exportStill, its statuses saying its frames.
   */
  exportMovie(
    width: number,
    height: number,
    frames: number,
    rock: number,
  ): Promise<ExportStatusMessage> {
    return this.request({ type: 'export_movie', width, height, frames, rock });
  }

  /** Stops an export of this connection; its last status says `cancelled`. */
  cancelExport(id: string): void {
    this.sendMessage({ type: 'cancel_export', export: id });
  }

  /**
   * Where a finished export is downloaded from: its URL on the server, with the access token and
   * the session's volume, which a cluster's proxy routes by to the server that holds it.
   */
  downloadUrl(status: ExportStatusMessage): string | undefined {
    if (status.url === undefined) return undefined;
    const url = new URL(status.url, this.url.replace(/^ws/, 'http'));
    if (this.route.volume !== undefined) url.searchParams.set('volume', this.route.volume);
    const token = this.options.accessToken;
    if (token !== undefined && token !== '') url.searchParams.set('token', token);
    return url.toString();
  }

  /** Draws `volume` (an id from `volumes`) as the session's label map (owner only). */
  async addLabels(volume: string): Promise<SessionInfo> {
    return this.changeLabels(await this.request({ type: 'add_labels', volume }));
  }

  /** Draws no label map (owner only). */
  async removeLabels(): Promise<SessionInfo> {
    return this.changeLabels(await this.request({ type: 'remove_labels' }));
  }

  private changeLabels(answer: LabelsMessage): SessionInfo {
    const session = this.session;
    if (!session || session.session !== answer.session) {
      throw new RequestFailed(`${answer.type}: the session changed meanwhile`);
    }
    this.takeLabels(session, answer);
    return session;
  }

  /**
   * What lies under the point (x, y) of the session's view, fractions of its width and height
   * from its top-left; any viewer may ask.
   */
  pick(x: number, y: number): Promise<PickedMessage> {
    return this.request({ type: 'pick', x, y });
  }

  async stats(): Promise<Record<string, unknown>> {
    return (await this.request({ type: 'stats' })).stats;
  }

  /** Leaves the session (the connection stays open). */
  async leave(): Promise<void> {
    this.wanted = null;
    await this.request({ type: 'close' });
    this.session = null;
  }
}

/** Whether `labels` names every label `styles` styles, and no other: the same map. */
export function namesTheLabels(labels: LabelSummary[], styles: Record<string, unknown>): boolean {
  return (
    labels.length === Object.keys(styles).length &&
    labels.every((l) => styles[String(l.id)] !== undefined)
  );
}
