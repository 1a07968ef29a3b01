// The server's names and views for the web client, written from its C++ tables by
// scripts/update-schema.sh; protocol_test (SchemaAgreement.TheWebClientsServerTablesAreGenerated)
// fails while this file differs from what they make. Not edited by hand.

/** The formats frames are written in, the first the default. */
export const ENCODINGS = ['jpeg', 'png', 'h264'] as const;
/** The codes an `error` message carries. */
export const ERROR_CODES = ['malformed_json', 'invalid_message', 'unknown_type', 'unknown_field', 'unsupported_version', 'invalid_value', 'out_of_range', 'message_too_large', 'rate_limited', 'unknown_volume', 'volume_unreadable', 'unknown_session', 'no_session', 'too_many_sessions', 'session_owned', 'render_failed', 'too_much_work', 'internal_error'] as const;
/** Where the server's listing of its data folder stands (volumes.listing). */
export const LISTINGS = ['scanning', 'complete', 'cut_short'] as const;
/** settings.compositing */
export const COMPOSITINGS = ['alpha', 'extinction'] as const;
/** settings.reconstruction */
export const RECONSTRUCTIONS = ['trilinear', 'tricubic'] as const;
/** settings.stage: the ray caster's stage. */
export const STAGES = ['compute', 'fragment'] as const;
/** settings.light_buffer.builder */
export const BUILDERS = ['per_slice', 'multi_slice'] as const;
/** settings.light_buffer.lookup */
export const LIGHT_LOOKUPS = ['interpolate', 'local'] as const;
/** light.type */
export const LIGHT_TYPES = ['directional', 'point'] as const;
/** Where a transfer function's positions lie: fractions of the volume's range, or Hounsfield units. */
export const POSITION_SPACES = ['normalized', 'hounsfield'] as const;
/** A mode's technique (hello.modes). */
export const TECHNIQUES = ['ray_casting', 'half_angle_slicing'] as const;
/** How a mode shadows (hello.modes). */
export const SHADOW_KINDS = ['none', 'light_buffer', 'rays'] as const;
/** What a mode scatters with (hello.modes). */
export const SCATTERING_KINDS = ['none', 'shell', 'cone'] as const;
/** When a mode reads gradients (hello.modes). */
export const GRADIENTS = ['never', 'with_phong', 'always'] as const;
/** The views named by anatomy (world space is RAS: +x right, +y anterior, +z superior). */
export const VIEWS = ['anterior', 'posterior', 'left', 'right', 'superior', 'inferior'] as const;

/** Each view's eye direction from its target (a unit vector) and its up, as the server poses them. */
export const VIEW_POSES: Readonly<
  Record<(typeof VIEWS)[number], { side: readonly [number, number, number]; up: readonly [number, number, number] }>
> = {
  anterior: { side: [0, 1, 0], up: [0, 0, 1] },
  posterior: { side: [0, -1, 0], up: [0, 0, 1] },
  left: { side: [-1, 0, 0], up: [0, 0, 1] },
  right: { side: [1, 0, 0], up: [0, 0, 1] },
  superior: { side: [0, 0, 1], up: [0, 1, 0] },
  inferior: { side: [0, 0, -1], up: [0, 1, 0] },
};

/** The space of a transfer function's positions when it names none. */
export const DEFAULT_POSITION_SPACE: (typeof POSITION_SPACES)[number] = 'normalized';
/** The name of a transfer function given by its points that names none. */
export const UNNAMED_TRANSFER_FUNCTION = 'custom';

/** How far from the horizon an orbit's eye goes, in degrees (the server keeps it short of the poles). */
export const MAX_ORBIT_ELEVATION = 89.9;
/** How far the default camera and the named views stand from the target, in box units. */
export const DEFAULT_CAMERA_DISTANCE = 2.6;
/** The default camera's vertical field of view, in degrees. */
export const DEFAULT_FOV = 30;

/** A point or a direction in world space (RAS), or a colour's channels. */
export type Vec3 = [number, number, number];
/** An image's width and height in pixels. */
export type Size = [number, number];

/**
 * Every setting a session's state holds, by its path: its kind, its range (each component's; `limited`:
 * bounded by hello.limits instead, at its default here) or its names, and what it does.
 */
export const SETTINGS = {
  'camera/eye': { kind: 'vector', min: -1000, max: 1000, summary: "camera position" },
  'camera/target': { kind: 'vector', min: -1000, max: 1000, summary: "the point the camera looks at" },
  'camera/up': { kind: 'vector', min: -1000, max: 1000, summary: "the camera's up direction" },
  'camera/fov': { kind: 'number', min: 1, max: 170, summary: "vertical field of view in degrees" },
  'light/type': { kind: 'choice', choices: ['directional', 'point'], summary: "a directional light, or a point light" },
  'light/direction': { kind: 'vector', min: -1000, max: 1000, summary: "toward a directional light; not zero for one" },
  'light/position': { kind: 'vector', min: -1000, max: 1000, summary: "a point light's position" },
  'light/color': { kind: 'vector', min: 0, max: 1, summary: "light colour" },
  'light/intensity': { kind: 'number', min: 0, max: 100, summary: "light intensity" },
  'light/ambient': { kind: 'number', min: 0, max: 1, summary: "ambient light, a fraction of the light colour" },
  'settings/mode': { kind: 'choice', choices: ['dvr', 'phong', 'half_angle', 'sbrc', 'sbrc_shell', 'sbrc_cone', 'reference'], summary: "rendering mode" },
  'settings/compositing': { kind: 'choice', choices: ['alpha', 'extinction'], summary: "compositing" },
  'settings/reconstruction': { kind: 'choice', choices: ['trilinear', 'tricubic'], summary: "volume filter between voxels: trilinear, or the smoother tricubic B-spline (about 8 times the fetches)" },
  'settings/stage': { kind: 'choice', choices: ['compute', 'fragment'], summary: "where the ray caster runs" },
  'settings/size': { kind: 'size', min: 1, max: 2048, limited: true, summary: "image size" },
  'settings/sample_distance': { kind: 'number', min: 6.103515625e-05, max: 2, summary: "ray step, unit = the volume's longest side" },
  'settings/opacity_unit_distance': { kind: 'number', min: 0.0001, max: 1, summary: "distance the TF opacity refers to" },
  'settings/early_termination': { kind: 'number', min: 0.01, max: 1, summary: "stop a ray once its opacity reaches this" },
  'settings/background': { kind: 'vector', min: 0, max: 1, summary: "background colour" },
  'settings/phong': { kind: 'boolean', summary: "Blinn-Phong on top of shadows (shadow modes)" },
  'settings/empty_space_skipping': { kind: 'boolean', summary: "leap over the bricks the transfer function leaves transparent (the same image, faster)" },
  'settings/jitter': { kind: 'boolean', summary: "ray-cast modes: per-pixel jittered sample offsets (fine noise instead of rings)" },
  'settings/preintegration': { kind: 'boolean', summary: "classify the segment between two samples by both values (pre-integrated TF): no rings of the step on steep TFs" },
  'cut/crop/enabled': { kind: 'boolean', summary: "draw only what lies inside the crop box" },
  'cut/crop/min': { kind: 'vector', min: -10000, max: 10000, summary: "the crop box's corner toward the patient's left, posterior and inferior (RAS, mm)" },
  'cut/crop/max': { kind: 'vector', min: -10000, max: 10000, summary: "the crop box's corner toward the patient's right, anterior and superior (RAS, mm)" },
  'cut/plane_1/enabled': { kind: 'boolean', summary: "cut by this plane, keeping the side its normal points to" },
  'cut/plane_1/point': { kind: 'vector', min: -10000, max: 10000, summary: "a point of the plane (RAS, mm)" },
  'cut/plane_1/normal': { kind: 'vector', min: -1, max: 1, summary: "the plane's normal, toward the side kept (RAS); not zero" },
  'cut/plane_2/enabled': { kind: 'boolean', summary: "cut by this plane, keeping the side its normal points to" },
  'cut/plane_2/point': { kind: 'vector', min: -10000, max: 10000, summary: "a point of the plane (RAS, mm)" },
  'cut/plane_2/normal': { kind: 'vector', min: -1, max: 1, summary: "the plane's normal, toward the side kept (RAS); not zero" },
  'cut/plane_3/enabled': { kind: 'boolean', summary: "cut by this plane, keeping the side its normal points to" },
  'cut/plane_3/point': { kind: 'vector', min: -10000, max: 10000, summary: "a point of the plane (RAS, mm)" },
  'cut/plane_3/normal': { kind: 'vector', min: -1, max: 1, summary: "the plane's normal, toward the side kept (RAS); not zero" },
  'cut/plane_4/enabled': { kind: 'boolean', summary: "cut by this plane, keeping the side its normal points to" },
  'cut/plane_4/point': { kind: 'vector', min: -10000, max: 10000, summary: "a point of the plane (RAS, mm)" },
  'cut/plane_4/normal': { kind: 'vector', min: -1, max: 1, summary: "the plane's normal, toward the side kept (RAS); not zero" },
  'cut/plane_5/enabled': { kind: 'boolean', summary: "cut by this plane, keeping the side its normal points to" },
  'cut/plane_5/point': { kind: 'vector', min: -10000, max: 10000, summary: "a point of the plane (RAS, mm)" },
  'cut/plane_5/normal': { kind: 'vector', min: -1, max: 1, summary: "the plane's normal, toward the side kept (RAS); not zero" },
  'cut/plane_6/enabled': { kind: 'boolean', summary: "cut by this plane, keeping the side its normal points to" },
  'cut/plane_6/point': { kind: 'vector', min: -10000, max: 10000, summary: "a point of the plane (RAS, mm)" },
  'cut/plane_6/normal': { kind: 'vector', min: -1, max: 1, summary: "the plane's normal, toward the side kept (RAS); not zero" },
  'cut/casts_shadows': { kind: 'boolean', summary: "what the cut removes still casts shadows (context); off: it neither shows nor shadows (virtual dissection)" },
  'settings/frame_budget_ms': { kind: 'number', min: 0, max: 60000, summary: "milliseconds a frame may take: the server picks the method and quality; 0 = as set" },
  'settings/refinement_steps': { kind: 'integer', min: 0, max: 256, summary: "at most this many refinement steps follow a still frame (jittered ray casts); 0 = none" },
  'settings/refinement_threshold': { kind: 'number', min: 0, max: 255, summary: "refinement stops once a step changes the still by no more than this (RMS, 8-bit levels); 0 = only the step limit" },
  'settings/shading/diffuse': { kind: 'number', min: 0, max: 4, summary: "Blinn-Phong diffuse weight" },
  'settings/shading/specular': { kind: 'number', min: 0, max: 4, summary: "Blinn-Phong specular weight" },
  'settings/shading/shininess': { kind: 'number', min: 1, max: 1024, summary: "Blinn-Phong exponent" },
  'settings/light_buffer/slices': { kind: 'integer', min: 1, max: 1024, limited: true, summary: "light slices, also half-angle's slices" },
  'settings/light_buffer/resolution': { kind: 'integer', min: 1, max: 1024, limited: true, summary: "light buffer R x R texels" },
  'settings/light_buffer/builder': { kind: 'choice', choices: ['per_slice', 'multi_slice'], summary: "light-buffer builder" },
  'settings/light_buffer/compensation': { kind: 'number', min: 0, max: 1000, summary: "light-buffer darkening compensation, n in (1+alpha)^n; 0 = off" },
  'settings/light_buffer/slab_samples': { kind: 'integer', min: 0, max: 16, summary: "points per light slab: 1 = the slice plane (the paper), 0 = one per voxel" },
  'settings/light_buffer/lookup': { kind: 'choice', choices: ['interpolate', 'local'], summary: "camera samples read the light buffer: the layer nearer the light + a march through the rest of the slab (local), or the paper's interpolation between the two nearest layers" },
  'settings/scattering/shell_radius': { kind: 'number', min: 0.0001, max: 0.5, summary: "sbrc_shell: distance of the first ring of neighbours, world units" },
  'settings/scattering/shell_rings': { kind: 'integer', min: 1, max: 4, summary: "sbrc_shell: rings of neighbours" },
  'settings/scattering/shell_center_weight': { kind: 'number', min: 0, max: 1, summary: "sbrc_shell: the centre's weight" },
  'settings/scattering/cone_angle': { kind: 'number', min: 0.1, max: 80, summary: "sbrc_cone: angle of the cone of samples, in degrees" },
  'settings/scattering/cone_center_weight': { kind: 'number', min: 0, max: 1, summary: "sbrc_cone: the disc centre's weight" },
  'output/encoding': { kind: 'choice', choices: ['jpeg', 'png', 'h264'], summary: "the format frames are written in" },
  'output/jpeg_quality': { kind: 'integer', min: 1, max: 100, summary: "JPEG quality" },
  'output/h264_quality': { kind: 'integer', min: 1, max: 51, summary: "H.264 frames: x264's rate factor, 1 (nearly lossless) .. 51 (fewer bytes)" },
} as const;

/** A session's state as `state` carries it, but for the transfer function. */
export interface StateSettings {
  camera: {
    /** camera position */
    eye: Vec3;
    /** the point the camera looks at */
    target: Vec3;
    /** the camera's up direction */
    up: Vec3;
    /** vertical field of view in degrees */
    fov: number;
  };
  light: {
    /** a directional light, or a point light */
    type: 'directional' | 'point';
    /** toward a directional light; not zero for one */
    direction: Vec3;
    /** a point light's position */
    position: Vec3;
    /** light colour */
    color: Vec3;
    /** light intensity */
    intensity: number;
    /** ambient light, a fraction of the light colour */
    ambient: number;
  };
  settings: {
    /** rendering mode */
    mode: 'dvr' | 'phong' | 'half_angle' | 'sbrc' | 'sbrc_shell' | 'sbrc_cone' | 'reference';
    /** compositing */
    compositing: 'alpha' | 'extinction';
    /** volume filter between voxels: trilinear, or the smoother tricubic B-spline (about 8 times the fetches) */
    reconstruction: 'trilinear' | 'tricubic';
    /** where the ray caster runs */
    stage: 'compute' | 'fragment';
    /** image size */
    size: Size;
    /** ray step, unit = the volume's longest side */
    sample_distance: number;
    /** distance the TF opacity refers to */
    opacity_unit_distance: number;
    /** stop a ray once its opacity reaches this */
    early_termination: number;
    /** background colour */
    background: Vec3;
    /** Blinn-Phong on top of shadows (shadow modes) */
    phong: boolean;
    /** leap over the bricks the transfer function leaves transparent (the same image, faster) */
    empty_space_skipping: boolean;
    /** ray-cast modes: per-pixel jittered sample offsets (fine noise instead of rings) */
    jitter: boolean;
    /** classify the segment between two samples by both values (pre-integrated TF): no rings of the step on steep TFs */
    preintegration: boolean;
    /** milliseconds a frame may take: the server picks the method and quality; 0 = as set */
    frame_budget_ms: number;
    /** at most this many refinement steps follow a still frame (jittered ray casts); 0 = none */
    refinement_steps: number;
    /** refinement stops once a step changes the still by no more than this (RMS, 8-bit levels); 0 = only the step limit */
    refinement_threshold: number;
    shading: {
      /** Blinn-Phong diffuse weight */
      diffuse: number;
      /** Blinn-Phong specular weight */
      specular: number;
      /** Blinn-Phong exponent */
      shininess: number;
    };
    light_buffer: {
      /** light slices, also half-angle's slices */
      slices: number;
      /** light buffer R x R texels */
      resolution: number;
      /** light-buffer builder */
      builder: 'per_slice' | 'multi_slice';
      /** light-buffer darkening compensation, n in (1+alpha)^n; 0 = off */
      compensation: number;
      /** points per light slab: 1 = the slice plane (the paper), 0 = one per voxel */
      slab_samples: number;
      /** camera samples read the light buffer: the layer nearer the light + a march through the rest of the slab (local), or the paper's interpolation between the two nearest layers */
      lookup: 'interpolate' | 'local';
    };
    scattering: {
      /** sbrc_shell: distance of the first ring of neighbours, world units */
      shell_radius: number;
      /** sbrc_shell: rings of neighbours */
      shell_rings: number;
      /** sbrc_shell: the centre's weight */
      shell_center_weight: number;
      /** sbrc_cone: angle of the cone of samples, in degrees */
      cone_angle: number;
      /** sbrc_cone: the disc centre's weight */
      cone_center_weight: number;
    };
  };
  cut: {
    crop: {
      /** draw only what lies inside the crop box */
      enabled: boolean;
      /** the crop box's corner toward the patient's left, posterior and inferior (RAS, mm) */
      min: Vec3;
      /** the crop box's corner toward the patient's right, anterior and superior (RAS, mm) */
      max: Vec3;
    };
    plane_1: {
      /** cut by this plane, keeping the side its normal points to */
      enabled: boolean;
      /** a point of the plane (RAS, mm) */
      point: Vec3;
      /** the plane's normal, toward the side kept (RAS); not zero */
      normal: Vec3;
    };
    plane_2: {
      /** cut by this plane, keeping the side its normal points to */
      enabled: boolean;
      /** a point of the plane (RAS, mm) */
      point: Vec3;
      /** the plane's normal, toward the side kept (RAS); not zero */
      normal: Vec3;
    };
    plane_3: {
      /** cut by this plane, keeping the side its normal points to */
      enabled: boolean;
      /** a point of the plane (RAS, mm) */
      point: Vec3;
      /** the plane's normal, toward the side kept (RAS); not zero */
      normal: Vec3;
    };
    plane_4: {
      /** cut by this plane, keeping the side its normal points to */
      enabled: boolean;
      /** a point of the plane (RAS, mm) */
      point: Vec3;
      /** the plane's normal, toward the side kept (RAS); not zero */
      normal: Vec3;
    };
    plane_5: {
      /** cut by this plane, keeping the side its normal points to */
      enabled: boolean;
      /** a point of the plane (RAS, mm) */
      point: Vec3;
      /** the plane's normal, toward the side kept (RAS); not zero */
      normal: Vec3;
    };
    plane_6: {
      /** cut by this plane, keeping the side its normal points to */
      enabled: boolean;
      /** a point of the plane (RAS, mm) */
      point: Vec3;
      /** the plane's normal, toward the side kept (RAS); not zero */
      normal: Vec3;
    };
    /** what the cut removes still casts shadows (context); off: it neither shows nor shadows (virtual dissection) */
    casts_shadows: boolean;
  };
  output: {
    /** the format frames are written in */
    encoding: 'jpeg' | 'png' | 'h264';
    /** JPEG quality */
    jpeg_quality: number;
    /** H.264 frames: x264's rate factor, 1 (nearly lossless) .. 51 (fewer bytes) */
    h264_quality: number;
  };
}

/** hello.limits' numbers as a server configured with nothing else sends them. */
export const DEFAULT_LIMITS = {
  max_export_side: 4096,
  max_frame_work: 100000000000,
  max_hounsfield_position: 100000,
  max_image_side: 2048,
  max_json_depth: 16,
  max_light_resolution: 1024,
  max_message_bytes: 65536,
  max_movie_frames: 720,
  max_movie_side: 1920,
  max_requests_per_second: 120,
  max_send_queue: 4,
  max_sessions: 64,
  max_sessions_per_client: 16,
  max_sessions_per_connection: 4,
  max_slices: 1024,
  max_transfer_function_points: 256,
} as const;

/** The settings a new session starts from (as its `state` holds them), shown until its state arrives. */
export const DEFAULT_SETTINGS = {
  background: [0, 0, 0],
  compositing: 'alpha',
  early_termination: 0.99,
  empty_space_skipping: true,
  frame_budget_ms: 0,
  jitter: true,
  light_buffer: {
    builder: 'multi_slice',
    compensation: 0,
    lookup: 'local',
    resolution: 512,
    slab_samples: 0,
    slices: 128,
  },
  mode: 'sbrc',
  opacity_unit_distance: 0.00390625,
  phong: true,
  preintegration: false,
  reconstruction: 'trilinear',
  refinement_steps: 32,
  refinement_threshold: 0.25,
  sample_distance: 0.00390625,
  scattering: {
    cone_angle: 30,
    cone_center_weight: 0.2,
    shell_center_weight: 0.4,
    shell_radius: 0.0078125,
    shell_rings: 1,
  },
  shading: {
    diffuse: 0.75,
    shininess: 32,
    specular: 0.3,
  },
  size: [512, 512],
  stage: 'compute',
} as const;
/** The output a new session starts from. */
export const DEFAULT_OUTPUT = {
  encoding: 'jpeg',
  h264_quality: 22,
  jpeg_quality: 85,
} as const;
