/*
 * Values real frames hold, from plain C11 as an engine meets them: HDR colour over any albedo,
 * black and emissive surfaces, a camera far from the world's origin, infinite and out-of-range
 * depth, negative colour and a near plane that disagrees with the projection. Each case builds
 * a frame in C (a wall facing a still camera), submits it to a warp-only context, extrapolates
 * its halfway instant and checks the output and the statistics against what the header says.
 * Run on lavapipe under the validation layers with synchronization validation by
 * tests/c_abi.rs.
 *
 *   extremes_test
 *
 * Prints one line per case and exits 0 only when every case held and validation reported
 * nothing.
 */
#include "engine.h"

#include <math.h>

enum { WIDTH = 32, HEIGHT = 24, PIXELS = WIDTH * HEIGHT };

/* The wall's distance from the camera, and the projection's planes. */
static const float WALL = 5.0f, NEAR_PLANE = 0.1f, FAR_PLANE = 100.0f;

/* One instant as the engine holds it on the host, before upload. */
typedef struct Instant {
  float color[PIXELS * 4];
  float base_color[PIXELS * 4];
  float normal[PIXELS * 4];
  float depth[PIXELS];
  PatchexCamera camera;
} Instant;

/* A still camera at (0, 0, -eye_z) looking down -z (identity rotation), with a right-handed
   Vulkan projection; depth 0 at `near_z` for hardware depth (1 when reversed). */
static PatchexCamera camera(PatchexDepthConvention convention, float eye_z, float near_z) {
  PatchexCamera c;
  memset(&c, 0, sizeof c);
  const float f = 1.0f / tanf(0.5f), aspect = (float)WIDTH / HEIGHT;
  c.view[0] = c.view[5] = c.view[10] = c.view[15] = 1.0f;
  c.view[14] = eye_z;
  c.projection[0] = f / aspect;
  c.projection[5] = f;
  c.projection[11] = -1.0f;
  if (convention == PATCHEX_DEPTH_HARDWARE_REVERSED) {
    c.projection[10] = near_z / (FAR_PLANE - near_z);
    c.projection[14] = near_z * FAR_PLANE / (FAR_PLANE - near_z);
  } else {
    c.projection[10] = FAR_PLANE / (near_z - FAR_PLANE);
    c.projection[14] = near_z * FAR_PLANE / (near_z - FAR_PLANE);
  }
  c.near_plane = near_z;
  c.far_plane = FAR_PLANE;
  c.depth_convention = convention;
  return c;
}

/* The wall WALL units in front of the camera, facing it: colour `rgb` over base colour `base`,
   its depth as `convention` stores it. */
static void wall(Instant *at, PatchexDepthConvention convention, const float rgb[3], float base) {
  at->camera = camera(convention, 0.0f, NEAR_PLANE);
  const float *p = at->camera.projection;
  float depth = WALL;
  if (convention != PATCHEX_DEPTH_LINEAR_VIEW_Z) depth = (p[10] * -WALL + p[14]) / WALL;
  for (int i = 0; i < PIXELS; ++i) {
    for (int c = 0; c < 3; ++c) {
      at->color[4 * i + c] = rgb[c];
      at->base_color[4 * i + c] = base;
    }
    at->color[4 * i + 3] = at->base_color[4 * i + 3] = 1.0f;
    at->normal[4 * i + 0] = at->normal[4 * i + 1] = 0.0f;
    at->normal[4 * i + 2] = 1.0f;
    at->normal[4 * i + 3] = 0.0f;
    at->depth[i] = depth;
  }
}

static float half_to_float(uint16_t h) {
  const int exponent = (h >> 10) & 0x1f, mantissa = h & 0x3ff;
  const float sign = (h & 0x8000) ? -1.0f : 1.0f;
  if (exponent == 0) return sign * ldexpf((float)mantissa, -24);
  if (exponent == 31) return mantissa ? NAN : sign * INFINITY;
  return sign * ldexpf((float)(mantissa | 0x400), exponent - 25);
}

/* The output image's RGBA, as floats. */
static void read_output(Image *output, float *rgba) {
  static uint16_t halves[PIXELS * 4];
  read_image(output, halves);
  for (size_t i = 0; i < (size_t)PIXELS * 4; ++i) rgba[i] = half_to_float(halves[i]);
}

/* What one case gave back. */
typedef struct Outcome {
  PatchexResult submit, extrapolate;
  char message[512];
  float output[PIXELS * 4];
  PatchexFrameStats stats;
} Outcome;

static PatchexGeometry geometry_of(const Image *depth, const Image *normal, const Image *motion,
                                   const PatchexCamera *camera) {
  PatchexGeometry g;
  memset(&g, 0, sizeof g);
  g.depth = describe(depth);
  g.normal = describe(normal);
  g.normal_encoding = PATCHEX_NORMAL_SIGNED;
  g.motion_vectors = describe(motion);
  g.motion_vector_scale[0] = g.motion_vector_scale[1] = 1.0f;
  g.camera = *camera;
  return g;
}

/* Frame t `source` submitted to a new warp-only context, and the halfway instant `target`
   extrapolated from it (zero motion: the wall and the camera stand still). */
static void run(const Instant *source, const Instant *target, Outcome *out) {
  memset(out, 0, sizeof *out);
  PatchexCreateInfo info = create_info(PATCHEX_PRESET_WARP_ONLY, 1, NULL);
  PatchexContext *ctx = NULL;
  if (patchex_create(&info, &ctx) != PATCHEX_RESULT_SUCCESS) {
    fprintf(stderr, "patchex_create: %s\n", patchex_last_error(NULL));
    exit(2);
  }

  static float zero_motion[PIXELS * 2];
  const Instant *instants[2] = {source, target};
  Image color[2], base_color[2], normal[2], depth[2], motion[2];
  for (int i = 0; i < 2; ++i) {
    color[i] = input_image(VK_FORMAT_R32G32B32A32_SFLOAT, 16, (const void *)instants[i]->color);
    base_color[i] =
        input_image(VK_FORMAT_R32G32B32A32_SFLOAT, 16, (const void *)instants[i]->base_color);
    normal[i] = input_image(VK_FORMAT_R32G32B32A32_SFLOAT, 16, (const void *)instants[i]->normal);
    depth[i] = input_image(VK_FORMAT_R32_SFLOAT, 4, (const void *)instants[i]->depth);
    motion[i] = input_image(VK_FORMAT_R32G32_SFLOAT, 8, (const void *)zero_motion);
  }
  Image output = output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, VK_IMAGE_USAGE_STORAGE_BIT);

  begin();
  PatchexFrameDesc frame;
  memset(&frame, 0, sizeof frame);
  frame.header = header(PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof frame, NULL);
  frame.frame_index = 1;
  frame.queue_family_index = gpu.family;
  frame.width = WIDTH;
  frame.height = HEIGHT;
  frame.color = describe(&color[0]);
  frame.base_color = describe(&base_color[0]);
  frame.geometry = geometry_of(&depth[0], &normal[0], &motion[0], &source->camera);
  out->submit = patchex_submit_gbuffers(ctx, gpu.cmd, &frame);
  /* Without a frame there is nothing to extrapolate from. */
  out->extrapolate = out->submit;
  if (out->submit == PATCHEX_RESULT_SUCCESS) {
    PatchexExtrapolateDesc desc;
    memset(&desc, 0, sizeof desc);
    desc.header = header(PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof desc, NULL);
    desc.queue_family_index = gpu.family;
    desc.alpha = 0.5f;
    desc.width = WIDTH;
    desc.height = HEIGHT;
    desc.base_color = describe(&base_color[1]);
    desc.geometry = geometry_of(&depth[1], &normal[1], &motion[1], &target->camera);
    desc.output = describe(&output);
    out->extrapolate = patchex_extrapolate(ctx, gpu.cmd, &desc);
  }
  snprintf(out->message, sizeof out->message, "%s", patchex_last_error(ctx));
  submit_and_wait();
  if (out->extrapolate == PATCHEX_RESULT_SUCCESS) {
    read_output(&output, out->output);
    out->stats.header = header(PATCHEX_STRUCT_TYPE_FRAME_STATS, sizeof out->stats, NULL);
    expect(patchex_get_frame_stats(ctx, 1, &out->stats), PATCHEX_RESULT_SUCCESS,
           "patchex_get_frame_stats", ctx);
  }
  patchex_destroy(ctx);
  destroy_image(&output);
  for (int i = 0; i < 2; ++i) {
    Image *all[] = {&color[i], &base_color[i], &normal[i], &depth[i], &motion[i]};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) destroy_image(all[k]);
  }
}

/* Reports a case's check: counted as a failure when it does not hold. */
static void check(int holds, const char *name, const char *what) {
  if (!holds) {
    fprintf(stderr, "%s: %s does not hold\n", name, what);
    ++failures;
  }
}

static float largest_output(const Outcome *o) {
  float largest = 0.0f;
  for (int i = 0; i < PIXELS; ++i)
    for (int c = 0; c < 3; ++c)
      if (!(o->output[4 * i + c] <= largest)) largest = o->output[4 * i + c];
  return largest;
}

static float smallest_output(const Outcome *o) {
  float smallest = INFINITY;
  for (int i = 0; i < PIXELS; ++i)
    for (int c = 0; c < 3; ++c)
      if (!(o->output[4 * i + c] >= smallest)) smallest = o->output[4 * i + c];
  return smallest;
}

static Instant source, target;
static Outcome outcome;

/* Bright HDR colour comes back unchanged over any albedo, black included, and nothing is
   counted as sanitised. */
static void bright_colour_passes_through(void) {
  const float colours[2] = {30000.0f, 3000.0f};
  const float bases[5] = {0.0f, 0.2f, 0.5f, 0.8f, 1.0f};
  for (int i = 0; i < 2; ++i) {
    for (int b = 0; b < 5; ++b) {
      const float rgb[3] = {colours[i], colours[i], colours[i]};
      wall(&source, PATCHEX_DEPTH_LINEAR_VIEW_Z, rgb, bases[b]);
      target = source;
      run(&source, &target, &outcome);
      const char *name = "bright colour";
      check(outcome.extrapolate == PATCHEX_RESULT_SUCCESS, name, "success");
      /* Within one half-float step. */
      check(fabsf(largest_output(&outcome) - colours[i]) <= colours[i] / 1024.0f &&
                fabsf(smallest_output(&outcome) - colours[i]) <= colours[i] / 1024.0f,
            name, "output equals input");
      check(outcome.stats.source_sanitized_pixels == 0, name, "source_sanitized_pixels == 0");
      check(outcome.stats.extrapolations[0].sanitized_pixels == 0, name,
            "sanitized_pixels == 0");
    }
  }
  printf("bright colour over albedo 0 to 1: checked\n");
}

/* A black (or nearly black, or NaN) base colour in frame t and a lit one at the target: what is
   warped from the dark surface never comes back brighter than its colour, so the output stays
   within the input's range. */
static void black_source_does_not_blow_up(void) {
  const float bases[3] = {0.0f, 1e-7f, NAN};
  const float rgb[3] = {0.3f, 0.6f, 1.0f};
  for (int b = 0; b < 3; ++b) {
    wall(&source, PATCHEX_DEPTH_LINEAR_VIEW_Z, rgb, bases[b]);
    wall(&target, PATCHEX_DEPTH_LINEAR_VIEW_Z, rgb, 0.5f);
    run(&source, &target, &outcome);
    const char *name = "black base colour in frame t";
    check(outcome.extrapolate == PATCHEX_RESULT_SUCCESS, name, "success");
    check(largest_output(&outcome) <= 1.0f, name, "output <= largest input 1");
    uint32_t sanitized = isnan(bases[b]) ? PIXELS : 0;
    check(outcome.stats.source_sanitized_pixels == sanitized, name,
          "NaN base colours, and only they, counted");
  }
  printf("black, near-black and NaN base colour in frame t: checked\n");
}

/* A camera 1e7 units from the origin along z is valid, and a still scene comes back. */
static void far_camera_is_accepted(void) {
  const float rgb[3] = {0.25f, 0.5f, 0.75f};
  wall(&source, PATCHEX_DEPTH_LINEAR_VIEW_Z, rgb, 0.5f);
  source.camera = camera(PATCHEX_DEPTH_LINEAR_VIEW_Z, 1e7f, NEAR_PLANE);
  target = source;
  run(&source, &target, &outcome);
  const char *name = "camera 1e7 from the origin";
  check(outcome.submit == PATCHEX_RESULT_SUCCESS, name, "submit succeeds");
  check(outcome.extrapolate == PATCHEX_RESULT_SUCCESS, name, "extrapolate succeeds");
  check(fabsf(largest_output(&outcome) - 0.75f) <= 1e-3f &&
            fabsf(smallest_output(&outcome) - 0.25f) <= 1e-3f,
        name, "the still wall comes back");
  check(outcome.stats.extrapolations[0].hole_fraction == 0.0f, name, "no holes");
  printf("camera 1e7 from the origin: checked\n");
}

/* Depth the engine cannot mean: every pixel counted as invalid geometry, and a hole. +infinity
   in linear depth is sky instead, and nothing is counted. */
static void unusable_depth_is_counted_and_a_hole(void) {
  const struct {
    PatchexDepthConvention convention;
    float depth;
    int usable;
  } cases[5] = {
      {PATCHEX_DEPTH_HARDWARE, INFINITY, 0},  {PATCHEX_DEPTH_HARDWARE, -0.5f, 0},
      {PATCHEX_DEPTH_HARDWARE, 1.5f, 0},      {PATCHEX_DEPTH_LINEAR_VIEW_Z, -5.0f, 0},
      {PATCHEX_DEPTH_LINEAR_VIEW_Z, INFINITY, 1},
  };
  const float rgb[3] = {0.5f, 0.5f, 0.5f};
  for (int i = 0; i < 5; ++i) {
    wall(&source, cases[i].convention, rgb, 0.5f);
    for (int p = 0; p < PIXELS; ++p) source.depth[p] = cases[i].depth;
    target = source;
    run(&source, &target, &outcome);
    char name[96];
    snprintf(name, sizeof name, "depth %g (convention %u)", (double)cases[i].depth,
             cases[i].convention);
    const PatchexExtrapolationStats *e = &outcome.stats.extrapolations[0];
    check(outcome.extrapolate == PATCHEX_RESULT_SUCCESS, name, "success");
    uint32_t invalid = cases[i].usable ? 0 : PIXELS;
    check(outcome.stats.source_invalid_geometry_pixels == invalid, name,
          "source_invalid_geometry_pixels");
    check(e->invalid_geometry_pixels == invalid, name, "invalid_geometry_pixels");
    check(e->hole_fraction == (cases[i].usable ? 0.0f : 1.0f), name,
          "hole_fraction counts the invalid pixels");
    check(((e->render_instead_reasons & PATCHEX_RENDER_INSTEAD_DISOCCLUSION) != 0) ==
              !cases[i].usable,
          name, "render instead when all is hole");
    check(largest_output(&outcome) <= 0.5f && smallest_output(&outcome) >= 0.0f, name,
          "output finite and within the input's range");
  }
  printf("infinite and out-of-range depth: checked\n");
}

/* Negative colour is not light: set to 0 and counted. */
static void negative_colour_is_counted(void) {
  const float rgb[3] = {-1.0f, 0.5f, 0.5f};
  wall(&source, PATCHEX_DEPTH_LINEAR_VIEW_Z, rgb, 0.5f);
  target = source;
  run(&source, &target, &outcome);
  const char *name = "negative colour";
  check(outcome.extrapolate == PATCHEX_RESULT_SUCCESS, name, "success");
  check(outcome.stats.source_sanitized_pixels == PIXELS, name,
        "every pixel counted in source_sanitized_pixels");
  check(smallest_output(&outcome) == 0.0f, name, "output never negative");
  printf("negative colour: checked\n");
}

/* A near plane other than the one the projection puts depth 0 at is refused, with a message. */
static void disagreeing_near_plane_is_refused(void) {
  const float rgb[3] = {0.5f, 0.5f, 0.5f};
  wall(&source, PATCHEX_DEPTH_HARDWARE, rgb, 0.5f);
  source.camera.near_plane = 0.5f;
  target = source;
  run(&source, &target, &outcome);
  const char *name = "near plane disagreeing with the projection";
  check(outcome.submit == PATCHEX_RESULT_ERROR_INVALID_ARGUMENT, name, "invalid argument");
  check(strstr(outcome.message, "near_plane") != NULL, name, "the message names near_plane");
  printf("near plane disagreeing with the projection: checked (%s)\n", outcome.message);
}

int main(void) {
  if (patchex_abi_version() != PATCHEX_ABI_VERSION) {
    fprintf(stderr, "library ABI %u, header ABI %u\n", patchex_abi_version(),
            PATCHEX_ABI_VERSION);
    return 1;
  }
  width = WIDTH;
  height = HEIGHT;
  create_gpu();
  bright_colour_passes_through();
  black_source_does_not_blow_up();
  far_camera_is_accepted();
  unusable_depth_is_counted_and_a_hole();
  negative_colour_is_counted();
  disagreeing_near_plane_is_refused();
  destroy_gpu();
  return verdict();
}
