// Wiring only: builds the view, the panels and the connection and connects their events.

import GUI from 'lil-gui';
import './style.css';
import { Connection, RequestFailed, ServerError, type SessionInfo } from './protocol/connection';
import {
  DEFAULT_LIMITS,
  mergePatches,
  VIEWS,
  type Camera,
  type Listing,
  type StatePatch,
  type VolumeSummary,
  withoutRefusedLabels,
} from './protocol/messages';
import { attachOrbitControls, OrbitCamera } from './interaction/orbit_camera';
import { RenderPacer } from './interaction/pacing';
import { FrameView } from './view/frame_view';
import { canDecodeH264, chooseEncoding } from './view/video_support';
import { RefinementBadge } from './view/refinement_badge';
import { StatsOverlay } from './view/stats_overlay';
import { Notices } from './view/notices';
import { OrientationMarker } from './view/orientation_marker';
import { VolumePicker } from './panels/volume_picker';
import { SessionPanel } from './panels/session_panel';
import { LightControl } from './panels/light_control';
import { MethodPanel } from './panels/method_panel';
import { CutPanel } from './panels/cut_panel';
import { placementOf } from './panels/crop_box';
import { CropBoxOverlay } from './view/crop_box_overlay';
import { TfEditor } from './panels/tf_editor';
import { TfModel, tfTerms } from './panels/tf_model';
import { LabelsPanel } from './panels/labels_panel';
import { ExportPanel } from './panels/export_panel';
import { PickOverlay } from './view/pick_overlay';
import { attachTap } from './interaction/tap';

const query = new URLSearchParams(location.search);
// Asked once; sessions are opened after it answers (openVolume).
const h264Support = canDecodeH264();
let h264Decodable = false;
void h264Support.then((yes) => (h264Decodable = yes));
// The encoding the user chose in the Image panel: the next session this page opens keeps it.
let chosenEncoding: string | null = null;
const joinId = query.get('join');
// The page's ?volume= (with ?join=, the session's volume) routes the first WebSocket to the server
// that holds it; ?token= is the access token a deployment asks for (README, Deploy).
const pageVolume = query.get('volume') ?? undefined;
const wsUrl =
  query.get('server') ?? `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`;

const viewElement = document.getElementById('view') as HTMLElement;
const panelElement = document.getElementById('panel') as HTMLElement;
const view = new FrameView(viewElement);
const stats = new StatsOverlay(viewElement);
const refinementBadge = new RefinementBadge(viewElement);
view.onShown((shown) => refinementBadge.show(shown.header));
view.onShown((shown) => stats.decoded(performance.now() - shown.receivedAt));
const tfModel = new TfModel();
const connection = new Connection(wsUrl, {
  accessToken: query.get('token') ?? undefined,
  route: { volume: pageVolume, session: joinId ?? undefined },
});
const notices = new Notices(document.body, () => connection.retryNow());
view.onUndecodable(() =>
  notices.show(
    'warning',
    'Frames this browser cannot decode',
    "This session's frames come as H.264, which this browser cannot decode: it shows the stills only. " +
      'The owner can choose JPEG in Method & quality → Image.',
  ),
);

const camera = new OrbitCamera();
const marker = new OrientationMarker(viewElement);
marker.update(camera.toCamera());
let role: SessionInfo['role'] = 'none';
let scale = 1;

// ---- outgoing changes: merged, and sent with the next paced render ------------------------------
let pendingPatch: StatePatch | null = null;
/** Each render request: when it was sent and the camera its frame is drawn with. */
const sent = new Map<number, { at: number; camera: Camera }>();

function describe(e: unknown): string {
  return e instanceof ServerError ? e.describe() : e instanceof Error ? e.message : String(e);
}

function showSessionState(): void {
  const state = connection.session?.state;
  if (!state) return;
  light.update(state.light);
  cutPanel.update(state);
  method.update(state);
  labelsPanel.update(state, connection.session?.labels);
}

/** The session's labels as the server answered: not while a change of them waits to be sent. */
function showLabels(): void {
  if (pendingPatch?.labels) return;
  labelsPanel.update(connection.session?.state, connection.session?.labels);
}

/** A change of the labels not yet sent is dropped: the map it was for goes. */
function dropPendingLabels(): void {
  if (pendingPatch) pendingPatch = withoutRefusedLabels(pendingPatch);
}

const pacer = new RenderPacer((interactive) => {
  if (!connection.connected || !connection.session || connection.restoring) return null;
  if (pendingPatch && role === 'owner') {
    const patch = pendingPatch;
    pendingPatch = null;
    // The frame changes after the pick's answer (the server answers in order): it may no longer
    // show what the callout names.
    pick.clear();
    connection.set(patch).then(showLabels, (e: unknown) => {
      if (e instanceof RequestFailed) return; // connection lost: restored on reconnect
      notices.show('error', 'The server refused a change', describe(e));
      showSessionState(); // the controls show what the server has
    });
  }
  const id = connection.render(interactive);
  sent.set(id, { at: performance.now(), camera: camera.toCamera() });
  if (sent.size > 64) sent.delete(sent.keys().next().value as number);
  return id;
});

pacer.listenTo(connection);

function change(patch: StatePatch, interactive: boolean): void {
  if (role !== 'owner') return;
  pendingPatch = pendingPatch ? mergePatches(pendingPatch, patch) : patch;
  pacer.request(interactive);
}

function renderSize(): [number, number] {
  return view.renderSize(
    scale,
    connection.hello?.limits.max_image_side ?? DEFAULT_LIMITS.max_image_side,
  );
}

// ---- panels ------------------------------------------------------------------------------------
const gui = new GUI({ container: panelElement, title: 'Penumbra', width: 300 });
const picker = new VolumePicker(
  gui.addFolder('Volume'),
  (id) => void openVolume(id),
  () => void refreshVolumes(),
);
const sessionPanel = new SessionPanel(gui.addFolder('Shared viewing'));
const tfFolder = gui.addFolder('Transfer function');
const tfEditor = new TfEditor(tfFolder, tfModel, (interactive) =>
  change({ transfer_function: tfModel.toProtocol() }, interactive),
);
const lightFolder = gui.addFolder('Light');
const light = new LightControl(lightFolder, () => camera.toCamera(), change);
const cutPanel = new CutPanel(gui.addFolder('Cut'), change, () => camera.toCamera());
const labelsPanel = new LabelsPanel(gui.addFolder('Labels'), {
  change,
  add: (volume) => void drawLabels(volume),
  remove: () => void drawLabels(null),
});
const cropBox = new CropBoxOverlay(viewElement, cutPanel);
cutPanel.onBoxChange(() => cropBox.draw());
// The box is drawn with the camera of the frame on screen: the owner's camera when it asked for
// that frame; a viewer's follows the session's state.
view.onShown(({ header }) =>
  cropBox.setFrame({
    camera: (role === 'owner' ? sent.get(header.request)?.camera : undefined) ?? camera.toCamera(),
    width: header.width,
    height: header.height,
  }),
);
const method = new MethodPanel(
  gui.addFolder('Method & quality'),
  (patch, interactive) => {
    if (patch.output?.encoding !== undefined) chosenEncoding = patch.output.encoding;
    change(patch, interactive);
  },
  (s) => {
    scale = s;
    change({ settings: { size: renderSize() } }, false);
  },
);
const exportPanel = new ExportPanel(gui.addFolder('Export'), {
  start: (request) =>
    request.kind === 'still'
      ? connection.exportStill(request.width, request.height)
      : connection.exportMovie(request.width, request.height, request.frames, request.rock),
  cancel: (id) => connection.cancelExport(id),
  viewSize: () => view.devicePixels,
  downloadUrl: (status) => connection.downloadUrl(status),
});
const viewFolder = gui.addFolder('View');
const viewParams = {
  stats: window.innerWidth >= 600, // small screens: off until asked for (S or the panel)
  'reset camera': () => {
    camera.reset();
    cameraMoved();
  },
};
stats.visible = viewParams.stats;
viewFolder
  .add(viewParams, 'stats')
  .name('stats overlay (S)')
  .onChange((v: boolean) => (stats.visible = v));
viewFolder.add(viewParams, 'reset camera').name('reset camera (R)');
const help = document.createElement('div');
help.className = 'hint help';
help.innerHTML =
  'Drag: orbit · right/shift-drag: pan · wheel or pinch: zoom · two fingers: pan + zoom<br>' +
  'Keys (on the image): arrows orbit, shift+arrows pan, +/− zoom, R reset, S stats';
viewFolder.$children.appendChild(help);

function setEnabled(owner: boolean): void {
  picker.setEnabled(true);
  tfEditor.setEnabled(owner);
  light.setEnabled(owner);
  cutPanel.setEnabled(owner);
  labelsPanel.setEnabled(owner);
  method.setEnabled(owner);
  document.body.classList.toggle('viewer', !owner);
  viewButtons.querySelectorAll('button').forEach((b) => (b.disabled = !owner));
}

// ---- camera ------------------------------------------------------------------------------------
function cameraMoved(interactive = false): void {
  pick.clear(); // what lay under the point lies elsewhere now
  marker.update(camera.toCamera());
  light.cameraMoved();
  change({ camera: camera.toCamera() }, interactive);
}

// The views named by anatomy (the server's), over the image beside the orientation marker.
const viewButtons = document.createElement('div');
viewButtons.className = 'view-buttons';
viewButtons.setAttribute('role', 'toolbar');
viewButtons.setAttribute('aria-label', 'views');
for (const name of VIEWS) {
  const button = document.createElement('button');
  button.type = 'button';
  button.textContent = name[0]!.toUpperCase();
  button.title = `${name} view`;
  button.dataset.view = name;
  button.addEventListener('click', () => {
    if (role !== 'owner') return;
    camera.setView(name);
    cameraMoved();
  });
  viewButtons.appendChild(button);
}
viewElement.appendChild(viewButtons);

// On a portrait tablet or phone the panel is a drawer over the view (style.css), opened here.
const drawerToggle = document.createElement('button');
drawerToggle.type = 'button';
drawerToggle.className = 'drawer-toggle';
drawerToggle.textContent = '☰';
drawerToggle.title = 'controls';
drawerToggle.setAttribute('aria-controls', 'panel');
drawerToggle.setAttribute('aria-expanded', 'false');
drawerToggle.addEventListener('click', () => {
  const open = document.body.classList.toggle('drawer-open');
  drawerToggle.setAttribute('aria-expanded', String(open));
});
viewElement.appendChild(drawerToggle);

// ---- pick: a tap on the image asks what lies there -------------------------------------------------
const pick = new PickOverlay(viewElement);
view.onShown(({ header }) => pick.setFrame({ width: header.width, height: header.height }));
view.onResize(() => pick.clear());

async function pickAt(clientX: number, clientY: number): Promise<void> {
  if (!connection.connected || !connection.session || connection.restoring) return;
  const point = pick.pointAt(clientX, clientY);
  if (!point) return; // beside the image
  const ticket = pick.start(point);
  try {
    const answer = await connection.pick(point.x, point.y);
    const label = answer.label ? labelsPanel.row(answer.label.id) : undefined;
    if (pick.answer(ticket, answer, label?.color) && answer.label) {
      labelsPanel.select(answer.label.id);
    }
  } catch (e) {
    pick.fail(ticket, describe(e));
  }
}

attachTap(view.canvas, (x, y) => void pickAt(x, y));
window.addEventListener('keydown', (e) => {
  if (e.key === 'Escape') pick.clear();
});

attachOrbitControls(view.canvas, camera, {
  start: () => pacer.startInteraction(),
  change: () => cameraMoved(pacer.interactive),
  end: () => pacer.endInteraction(),
  enabled: () => role === 'owner',
});

window.addEventListener('keydown', (e) => {
  const target = e.target as HTMLElement | null;
  if (target && /^(INPUT|SELECT|TEXTAREA)$/.test(target.tagName)) return;
  if ((e.key === 's' || e.key === 'S') && !e.ctrlKey && !e.metaKey) {
    stats.visible = !stats.visible;
    viewParams.stats = stats.visible;
    gui.controllersRecursive().forEach((c) => c.updateDisplay());
  }
});

let resizeTimer: ReturnType<typeof setTimeout> | null = null;
view.onResize(() => {
  if (resizeTimer !== null) clearTimeout(resizeTimer);
  resizeTimer = setTimeout(() => change({ settings: { size: renderSize() } }, false), 150);
});

// ---- connection ----------------------------------------------------------------------------------
connection.on('status', (status) => {
  notices.connection(status, wsUrl);
  if (status.kind === 'lost' || status.kind === 'unreachable') pacer.reset();
  // A connection's exports end with it (the server cancels them); their last word is lost.
  if (status.kind !== 'connected') exportPanel.connectionEnded();
  if (status.kind === 'connected') {
    method.setModes(status.hello.modes);
    method.setLimits(status.hello.limits);
    exportPanel.setLimits(status.hello.limits);
    method.setRanges(status.hello.ranges);
    light.setRanges(status.hello.ranges);
    camera.setRanges(status.hello.ranges);
    tfModel.terms = tfTerms(status.hello);
    tfEditor.termsChanged();
    pacer.setRequestRate(status.hello.limits.max_requests_per_second);
    // Not while moving to another volume's server: the open that moved it is under way.
    if (!connection.session && !connection.moving) void start();
  }
});

connection.on('session', (info, restored) => {
  role = info.role;
  pick.clear();
  view.restartStream(); // an H.264 stream starts anew at the session's next keyframe
  if (!restored || info.role === 'viewer') camera.setFrom(info.state.camera, !restored);
  marker.update(camera.toCamera());
  const [min, max] = info.volume.range;
  tfModel.domain = { min, max, hounsfield: info.volume.hounsfield };
  tfEditor.setHounsfield(info.volume.hounsfield);
  tfModel.load(info.state.transfer_function, false);
  tfEditor.setHistogram(info.histogram);
  tfEditor.refresh();
  // Labels changed while disconnected wait in pendingPatch, merged into whatever follows: where
  // the session came back without their map, or with another, the server would refuse that whole
  // set.
  if (restored && pendingPatch)
    pendingPatch = withoutRefusedLabels(pendingPatch, info.state.labels);
  light.setScene({ volume: info.volume, camera: info.state.camera });
  cutPanel.setVolume(info.volume);
  cropBox.setPlacement(placementOf(info.volume));
  showSessionState();
  picker.updateVolume(info.volume);
  picker.select(info.volume.id);
  if (volumesListed) labelsPanel.setVolumes(volumesListed, info.volume.id);
  sessionPanel.update(info);
  setEnabled(info.role === 'owner');
  stats.reset();
  if (info.role === 'owner') {
    const size = renderSize();
    const [w, h] = info.state.settings.size;
    const patch: StatePatch = {};
    if (size[0] !== w || size[1] !== h) patch.settings = { size };
    // A session this page opened takes the encoding it chooses; one it got back keeps its own.
    const encoding = restored
      ? info.state.output.encoding
      : chooseEncoding(
          connection.hello?.encodings ?? [],
          chosenEncoding ?? query.get('encoding'),
          h264Decodable,
        );
    if (encoding !== info.state.output.encoding) {
      patch.output = { encoding };
      method.update({ ...info.state, output: { ...info.state.output, encoding } });
    }
    if (Object.keys(patch).length > 0) change(patch, false);
    else pacer.request(false);
  } else {
    pacer.request(false); // viewers may render: fetch the current frame now
  }
  if (restored) {
    const how = {
      resumed:
        'Your session is yours again; its viewers kept watching (the share link still works).',
      recreated:
        'Its server went away: your session was re-opened on another with your settings (the share link still works; viewers follow).',
      reopened:
        'The volume was re-opened and your settings restored (the share link changed: viewers must join again).',
      rejoined: 'Joined the shared session again.',
    };
    notices.show('info', 'Reconnected', how[restored]);
  }
});

// A viewer's panels follow the owner: each of its changes arrives as the session's whole state.
connection.on('state', (info) => {
  pick.clear(); // the owner's change may alter what the frame shows at the point, not only where
  camera.setFrom(info.state.camera);
  marker.update(camera.toCamera());
  tfModel.load(info.state.transfer_function, false);
  tfEditor.refresh();
  showSessionState();
});

connection.on('frame', (frame) => {
  // A refinement step answers no new request: it only improves the still frame on screen. A
  // preview answers it first, so the still that follows it is no answer either.
  const refined = (frame.header.refinement ?? 0) > 0 || frame.header.preview === true;
  const request = sent.get(frame.header.request);
  const requestSent = role === 'owner' && !refined ? request?.at : undefined;
  const arrived = performance.now();
  view.show(frame);
  stats.add({
    header: frame.header,
    bytes: frame.bytes,
    at: arrived,
    latencyMs: requestSent === undefined ? undefined : arrived - requestSent,
  });
});

// A label map drawn or removed (by this owner, or by the owner a viewer watches), or told after a
// join or a resume. What the frame shows at a picked point changes with it.
connection.on('labels', () => {
  pick.clear();
  labelsPanel.update(connection.session?.state, connection.session?.labels);
  pacer.request(false);
});

connection.on('serverError', (error) => notices.show('error', 'Server error', error.describe()));

connection.on('exportStatus', (status) => exportPanel.show(status));
connection.on('problem', (message) => notices.show('warning', 'Problem', message));

connection.on('sessionLost', (session, outcome) => {
  const name = `${session.slice(0, 8)}…`;
  if (outcome === 'waiting') {
    notices.show(
      'info',
      'The shared session is gone from its server',
      `Waiting for its owner to re-open ${name}.`,
    );
  } else {
    notices.show(
      'error',
      'The shared session ended',
      `Session ${name} went away with its server and its owner did not re-open it. Open a volume of your own, or ask the owner for a new link.`,
    );
  }
});

let refreshing: Promise<void> | null = null;
let listing: Listing = 'complete';
/** The volumes last listed (null before the first list): the label maps offered come from it. */
let volumesListed: VolumeSummary[] | null = null;

/**
 * Lists the volumes; while the server's first scan of its data folder runs, asks again each second
 * until it ends or `enough` holds. One refresh at a time.
 */
function refreshVolumes(enough: () => boolean = () => false): Promise<void> {
  refreshing ??= (async () => {
    try {
      for (;;) {
        const listed = await connection.listVolumes();
        listing = listed.listing;
        picker.setVolumes(listed.volumes, connection.session?.volume.id ?? '');
        volumesListed = listed.volumes;
        labelsPanel.setVolumes(listed.volumes, connection.session?.volume.id ?? '');
        picker.setListing(listing);
        if (listing !== 'scanning' || enough()) return;
        await new Promise((resolve) => setTimeout(resolve, 1000));
      }
    } catch (e) {
      notices.show('error', 'Could not list the volumes', describe(e));
    } finally {
      refreshing = null;
    }
  })();
  return refreshing;
}

/** Draws `volume` as the session's label map, or none (null). */
async function drawLabels(volume: string | null): Promise<void> {
  if (role !== 'owner' || !connection.session) return;
  dropPendingLabels();
  labelsPanel.setBusy(volume ? `Loading ${volume}…` : 'Removing the label map…');
  try {
    if (volume) await connection.addLabels(volume);
    else await connection.removeLabels();
  } catch (e) {
    if (!(e instanceof RequestFailed && !connection.connected)) {
      notices.show(
        'error',
        volume ? `Could not draw ${volume} as labels` : 'Could not remove the label map',
        describe(e),
      );
    }
  } finally {
    labelsPanel.setBusy(null);
  }
}

async function openVolume(id: string): Promise<void> {
  // The session's encoding is chosen once it opens: H.264 only where the browser said it decodes.
  h264Decodable = await h264Support;
  try {
    pendingPatch = null;
    await connection.open(id);
    const url = new URL(location.href);
    url.searchParams.delete('join');
    url.searchParams.set('volume', id);
    history.replaceState(null, '', url);
  } catch (e) {
    notices.show('error', `Could not open ${id}`, describe(e));
  }
}

async function start(): Promise<void> {
  // A shared session needs no list first: the list follows.
  if (joinId) {
    try {
      await connection.join(joinId, pageVolume);
      void refreshVolumes();
      return;
    } catch (e) {
      notices.show(
        'error',
        'Could not join the shared session',
        `${describe(e)}. Opening a volume of your own instead.`,
      );
      const url = new URL(location.href);
      url.searchParams.delete('join');
      history.replaceState(null, '', url);
    }
  }
  await refreshVolumes(() => picker.listsPreferred(query.get('volume')));
  // The list keeps growing under the open volume until the scan ends.
  if (listing === 'scanning') void refreshVolumes();
  // A volume the user picked while the list was growing stands.
  if (connection.session) return;
  const id = picker.defaultVolume(query.get('volume'));
  if (id) await openVolume(id);
  else
    notices.show(
      'warning',
      'No volumes',
      'The server offers no volumes (see penumbra serve --data).',
    );
}

setEnabled(false);
connection.connect();
