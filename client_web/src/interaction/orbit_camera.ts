// Orbit camera: the model (target, azimuth, elevation, distance, fov → protocol Camera; no DOM)
// and the controls that turn mouse, trackpad, touch and keys into it.
//   mouse:     left drag orbit; right/middle drag or shift+drag pan; wheel zoom
//   trackpad:  two-finger scroll zoom (ctrl+scroll, i.e. pinch, zooms finer); click-drag orbit
//   touch:     one finger orbit; two fingers pinch zoom and pan together
//   keys:      arrows orbit, shift+arrows pan, + / - zoom, R reset (the element must have focus)

import {
  DEFAULT_CAMERA_DISTANCE,
  DEFAULT_FOV,
  MAX_ORBIT_ELEVATION,
  VIEW_POSES,
} from '../protocol/generated/server_tables';
import type { Camera, SettingRanges, Vec3, ViewName } from '../protocol/messages';
import { slopPx } from './slop';

/** An orbit: the eye around the target, as a `set`'s camera may give it (§5). */
export interface Orbit {
  azimuth?: number;
  elevation?: number;
  distance?: number;
}

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

/**
 * How far from the horizon the orbit goes: it keeps +z up, which turns about its axis at the pole,
 * so it stops 1° short of it (the server's orbit range reaches ±90 and applies
 * ±MAX_ORBIT_ELEVATION).
 */
const MAX_ELEVATION = 89;

interface Interval {
  min: number;
  max: number;
}

/**
 * How far the orbit may go, from the server's ranges (hello.ranges): its distance from the target
 * (`camera/orbit/distance`), its elevation (`camera/orbit/elevation`, within ±MAX_ELEVATION), and
 * where the target may be panned to: within the coordinates the server takes (`vec3`) by the
 * largest distance, so that every eye the orbit makes is one it takes too.
 */
export interface OrbitLimits {
  distance: Interval;
  elevation: Interval;
  target: Interval;
}

/** Before the server's hello: the elevation's own limit, the rest left to the server. */
const UNBOUNDED: OrbitLimits = {
  distance: { min: 0, max: Infinity },
  elevation: { min: -MAX_ELEVATION, max: MAX_ELEVATION },
  target: { min: -Infinity, max: Infinity },
};

export function orbitLimits(ranges: SettingRanges): OrbitLimits {
  const distance = ranges['camera/orbit/distance'] ?? UNBOUNDED.distance;
  const elevation = ranges['camera/orbit/elevation'] ?? UNBOUNDED.elevation;
  const coords = ranges['vec3'] ?? UNBOUNDED.target;
  let target = { min: coords.min + distance.max, max: coords.max - distance.max };
  if (!(target.min <= target.max)) {
    // The range is narrower than the orbit is wide: the target stays at its centre.
    const centre = (coords.min + coords.max) / 2;
    target = { min: centre, max: centre };
  }
  return {
    distance: { min: distance.min, max: distance.max },
    elevation: {
      min: Math.max(-MAX_ELEVATION, elevation.min),
      max: Math.min(MAX_ELEVATION, elevation.max),
    },
    target,
  };
}

function sub(a: Vec3, b: Vec3): Vec3 {
  return [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
}

function deg(radians: number): number {
  return (radians * 180) / Math.PI;
}

/** The eye an `orbit` puts around `target`, as the server does (§5): azimuth from +y toward +x about +z. */
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
  const [x, y, z] = sub(eye, target);
  const distance = Math.hypot(x, y, z);
  return {
    azimuth: deg(Math.atan2(x, y)),
    elevation: distance > 0 ? deg(Math.asin(Math.max(-1, Math.min(1, z / distance)))) : 0,
    distance,
  };
}

function cross(a: Vec3, b: Vec3): Vec3 {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}

function normalize(a: Vec3): Vec3 {
  const l = Math.hypot(a[0], a[1], a[2]) || 1;
  return [a[0] / l, a[1] / l, a[2] / l];
}

function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

/** Right, up and backward (toward the eye) unit vectors of a camera. */
export function cameraBasis(camera: Camera): { right: Vec3; up: Vec3; back: Vec3 } {
  const forward = normalize(sub(camera.target, camera.eye));
  let right = cross(forward, camera.up);
  if (Math.hypot(...right) < 1e-9) right = cross(forward, [0, 1, 0]);
  right = normalize(right);
  const up = normalize(cross(right, forward));
  return { right, up, back: [-forward[0], -forward[1], -forward[2]] };
}

function degrees(radians: number): number {
  return (radians * 180) / Math.PI;
}

/**
 * A view named by anatomy (proto/README.md `camera.view`) as orbit angles, from the server's pose
 * of it (VIEW_POSES: the side its eye lies on and its up). The orbit keeps +z up, so a view from
 * above or below (its up horizontal) stops at the orbit's elevation limit and takes its azimuth
 * from which way its up must point on the image: near the pole the image's up is the horizontal
 * direction away from the eye's side from above, toward it from below.
 */
export function viewAngles(view: ViewName): { azimuth: number; elevation: number } {
  const { side, up } = VIEW_POSES[view];
  const elevation = degrees(Math.asin(Math.max(-1, Math.min(1, side[2]))));
  if (Math.hypot(side[0], side[1]) > 1e-9) {
    return { azimuth: degrees(Math.atan2(side[0], side[1])), elevation };
  }
  const away = side[2] > 0 ? -1 : 1;
  return { azimuth: degrees(Math.atan2(away * up[0], away * up[1])), elevation };
}

export class OrbitCamera {
  target: Vec3 = [0, 0, 0];
  azimuth = 0; // the anterior view, as the server's default camera
  elevation = 0;
  distance = DEFAULT_CAMERA_DISTANCE;
  fov = DEFAULT_FOV;
  private home: Camera | null = null;
  private limits: OrbitLimits = UNBOUNDED;

  /** The server's ranges (its hello), which the orbit keeps within (orbitLimits). */
  setRanges(ranges: SettingRanges): void {
    this.limits = orbitLimits(ranges);
    this.elevation = this.clampElevation(this.elevation);
    this.distance = this.clampDistance(this.distance);
    this.target = this.target.map((c) => this.clampTarget(c)) as Vec3;
  }

  private clampElevation(elevation: number): number {
    return clamp(elevation, this.limits.elevation.min, this.limits.elevation.max);
  }

  private clampDistance(distance: number): number {
    return clamp(distance, this.limits.distance.min, this.limits.distance.max);
  }

  private clampTarget(coordinate: number): number {
    return clamp(coordinate, this.limits.target.min, this.limits.target.max);
  }

  /** Takes a protocol camera (the session's state); `asHome` makes it what reset() returns to. */
  setFrom(camera: Camera, asHome = false): void {
    const orbit = orbitOf(camera.eye, camera.target);
    this.target = [...camera.target];
    this.azimuth = orbit.azimuth;
    this.elevation = this.clampElevation(orbit.elevation);
    this.distance = this.clampDistance(orbit.distance);
    this.fov = camera.fov;
    if (asHome) this.home = structuredClone(camera);
  }

  toCamera(): Camera {
    return {
      eye: orbitEye(this.target, {
        azimuth: this.azimuth,
        elevation: this.elevation,
        distance: this.distance,
      }),
      target: [...this.target],
      up: [0, 0, 1],
      fov: this.fov,
    };
  }

  /** Drag by (dx, dy) pixels in a view `height` pixels tall: half a turn per view height. */
  rotate(dx: number, dy: number, height: number): void {
    const degreesPerPixel = 180 / Math.max(1, height);
    this.azimuth -= dx * degreesPerPixel;
    this.azimuth = ((((this.azimuth + 180) % 360) + 360) % 360) - 180;
    this.elevation = this.clampElevation(this.elevation + dy * degreesPerPixel);
  }

  /** Moves the target so the point under the cursor follows it (at the target's depth). */
  pan(dx: number, dy: number, height: number): void {
    const { right, up } = cameraBasis(this.toCamera());
    const unitsPerPixel =
      (2 * this.distance * Math.tan(((this.fov / 2) * Math.PI) / 180)) / Math.max(1, height);
    for (let i = 0; i < 3; ++i) {
      this.target[i] = this.clampTarget(
        this.target[i]! + (-dx * right[i]! + dy * up[i]!) * unitsPerPixel,
      );
    }
  }

  /** factor < 1 moves closer. */
  zoom(factor: number): void {
    if (!(factor > 0) || !Number.isFinite(factor)) return;
    this.distance = this.clampDistance(this.distance * factor);
  }

  /** Looks from that side of the patient, keeping the target, distance and field of view. */
  setView(view: ViewName): void {
    const { azimuth, elevation } = viewAngles(view);
    this.azimuth = azimuth;
    this.elevation = this.clampElevation(elevation);
  }

  reset(): void {
    if (this.home) this.setFrom(this.home);
  }
}

export interface OrbitControlCallbacks {
  /** The camera changed; `interactive` while a gesture goes on. */
  change: () => void;
  /** A gesture started (frames become interactive). */
  start: () => void;
  /** A gesture ended (a still frame is due). */
  end: () => void;
  /** Whether the person may move the camera (viewers may not). */
  enabled: () => boolean;
}

/** Wires pointer, wheel and key events of `element` to `camera`; returns a detach function. */
export function attachOrbitControls(
  element: HTMLElement,
  camera: OrbitCamera,
  callbacks: OrbitControlCallbacks,
): () => void {
  const pointers = new Map<number, { x: number; y: number }>();
  let mode: 'rotate' | 'pan' | 'touch' | null = null;
  let wheelTimer: ReturnType<typeof setTimeout> | null = null;
  let keyActive = false;
  const height = (): number => element.clientHeight || 1;

  const twoFinger = (): { mid: { x: number; y: number }; spread: number } | null => {
    const [a, b] = [...pointers.values()];
    if (!a || !b) return null;
    return {
      mid: { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2 },
      spread: Math.hypot(a.x - b.x, a.y - b.y),
    };
  };
  let lastTwo: ReturnType<typeof twoFinger> = null;
  /**
   * The press of a one-pointer orbit that has not yet moved past the tap's slop: a tap that wobbles
   * must not turn the camera. Past it, the orbit turns from the press, as far as the pointer went
   * since, so the slop neither lags the drag nor makes it turn less.
   */
  let press: { pointerId: number; x: number; y: number; slop: number } | null = null;

  const begin = (): void => {
    if (mode === null && wheelTimer === null && !keyActive) callbacks.start();
  };

  const onDown = (e: PointerEvent): void => {
    if (!callbacks.enabled()) return;
    element.focus({ preventScroll: true });
    if (pointers.size === 0) begin();
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    element.setPointerCapture?.(e.pointerId);
    press = null;
    if (pointers.size >= 2) {
      mode = 'touch';
      lastTwo = twoFinger();
    } else {
      const panButton = e.button === 1 || e.button === 2;
      mode = panButton || e.shiftKey || e.ctrlKey || e.metaKey ? 'pan' : 'rotate';
      if (mode === 'rotate') {
        press = { pointerId: e.pointerId, x: e.clientX, y: e.clientY, slop: slopPx(e.pointerType) };
      }
    }
    e.preventDefault();
  };

  const onMove = (e: PointerEvent): void => {
    let previous = pointers.get(e.pointerId);
    if (!previous || mode === null) return;
    if (mode === 'rotate' && press?.pointerId === e.pointerId) {
      const away = Math.hypot(e.clientX - press.x, e.clientY - press.y);
      if (away <= press.slop) {
        pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
        return;
      }
      previous = { x: press.x, y: press.y };
      press = null;
    }
    const dx = e.clientX - previous.x;
    const dy = e.clientY - previous.y;
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    if (mode === 'touch') {
      const now = twoFinger();
      if (now && lastTwo) {
        if (lastTwo.spread > 0 && now.spread > 0) camera.zoom(lastTwo.spread / now.spread);
        camera.pan(now.mid.x - lastTwo.mid.x, now.mid.y - lastTwo.mid.y, height());
      }
      lastTwo = now;
    } else if (mode === 'pan') {
      camera.pan(dx, dy, height());
    } else {
      camera.rotate(dx, dy, height());
    }
    if (dx !== 0 || dy !== 0) callbacks.change();
  };

  const onUp = (e: PointerEvent): void => {
    if (!pointers.delete(e.pointerId)) return;
    if (press?.pointerId === e.pointerId) press = null;
    if (pointers.size === 1 && mode === 'touch') {
      mode = 'rotate'; // lifting one of two fingers continues as a one-finger orbit
      lastTwo = null;
    } else if (pointers.size === 0) {
      mode = null;
      if (wheelTimer === null && !keyActive) callbacks.end();
    }
  };

  const onWheel = (e: WheelEvent): void => {
    if (!callbacks.enabled()) return;
    e.preventDefault();
    begin();
    const pixels =
      e.deltaMode === 1 ? e.deltaY * 16 : e.deltaMode === 2 ? e.deltaY * 400 : e.deltaY;
    // ctrl+wheel is how browsers report a trackpad pinch: finer steps.
    camera.zoom(Math.exp(pixels * (e.ctrlKey ? 0.01 : 0.0015)));
    callbacks.change();
    if (wheelTimer !== null) clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => {
      wheelTimer = null;
      if (mode === null && !keyActive) callbacks.end();
    }, 250);
  };

  const onKeyDown = (e: KeyboardEvent): void => {
    if (!callbacks.enabled() || e.altKey || e.metaKey || e.ctrlKey) return;
    const step = 15; // pixels
    const h = height();
    let handled = true;
    const move = (dx: number, dy: number): void =>
      e.shiftKey ? camera.pan(dx, dy, h) : camera.rotate(dx * 2, dy * 2, h);
    switch (e.key) {
      case 'ArrowLeft':
        move(-step, 0);
        break;
      case 'ArrowRight':
        move(step, 0);
        break;
      case 'ArrowUp':
        move(0, -step);
        break;
      case 'ArrowDown':
        move(0, step);
        break;
      case '+':
      case '=':
        camera.zoom(0.9);
        break;
      case '-':
      case '_':
        camera.zoom(1 / 0.9);
        break;
      case 'r':
      case 'R':
      case 'Home':
        camera.reset();
        break;
      default:
        handled = false;
    }
    if (!handled) return;
    e.preventDefault();
    if (!keyActive) {
      begin();
      keyActive = true;
    }
    callbacks.change();
  };

  const onKeyUp = (): void => {
    if (!keyActive) return;
    keyActive = false;
    if (mode === null && wheelTimer === null) callbacks.end();
  };

  const onContextMenu = (e: Event): void => e.preventDefault();

  element.addEventListener('pointerdown', onDown);
  element.addEventListener('pointermove', onMove);
  element.addEventListener('pointerup', onUp);
  element.addEventListener('pointercancel', onUp);
  element.addEventListener('wheel', onWheel, { passive: false });
  element.addEventListener('keydown', onKeyDown);
  element.addEventListener('keyup', onKeyUp);
  element.addEventListener('blur', onKeyUp);
  element.addEventListener('contextmenu', onContextMenu);
  return () => {
    element.removeEventListener('pointerdown', onDown);
    element.removeEventListener('pointermove', onMove);
    element.removeEventListener('pointerup', onUp);
    element.removeEventListener('pointercancel', onUp);
    element.removeEventListener('wheel', onWheel);
    element.removeEventListener('keydown', onKeyDown);
    element.removeEventListener('keyup', onKeyUp);
    element.removeEventListener('blur', onKeyUp);
    element.removeEventListener('contextmenu', onContextMenu);
  };
}
