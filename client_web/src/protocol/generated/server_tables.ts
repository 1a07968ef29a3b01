// The server's names and views for the web client, written from its C++ tables by
// scripts/update-schema.sh; protocol_test (SchemaAgreement.TheWebClientsServerTablesAreGenerated)
// fails while this file differs from what they make. Not edited by hand.

/** The formats frames are written in, the first the default. */
export const ENCODINGS = ['jpeg', 'png'] as const;
/** settings.compositing */
export const COMPOSITINGS = ['alpha', 'extinction'] as const;
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

/** hello.limits' numbers as a server configured with nothing else sends them. */
export const DEFAULT_LIMITS = {
  max_frame_work: 100000000000,
  max_hounsfield_position: 100000,
  max_image_side: 2048,
  max_json_depth: 16,
  max_light_resolution: 1024,
  max_message_bytes: 65536,
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
  jitter: false,
  light_buffer: {
    builder: 'multi_slice',
    compensation: 0,
    lookup: 'local',
    resolution: 256,
    slab_samples: 0,
    slices: 128,
  },
  mode: 'sbrc',
  opacity_unit_distance: 0.00390625,
  phong: true,
  refinement_steps: 8,
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
  jpeg_quality: 85,
} as const;
