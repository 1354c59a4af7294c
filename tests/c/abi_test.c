/*
 * The whole C ABI from plain C11, as a C engine meets it: written against the installed
 * <patchex.h> alone, compiled with -std=c11 -Wall -Wextra -pedantic -Werror and with `near` and
 * `far` defined as empty macros (as <windows.h> does), run on lavapipe under the validation
 * layers with synchronization validation. tests/c_abi.rs builds and runs it, then runs the same
 * calls through the Rust path and compares every output bit for bit.
 *
 *   abi_test DATA_DIR OUT_DIR WIDTH HEIGHT FI_WEIGHTS NEAR_BE_WEIGHTS
 *
 * DATA_DIR holds frame0.bin .. frame3.bin (rendered frames t-1 and t at 0 and 2, the instants
 * halfway to the next frame at 1 and 3), each: a PatchexCamera, then colour, base colour,
 * material, normal and colour without dynamic shadows as RGBA32F, depth, shadow mask and the
 * sun's visibility through static casters as R32F, motion vectors as RG32F and stencil ids as
 * R8_UINT; sun.bin, the sun's direction and illuminance (six floats); sky.bin, the side of the
 * sky's octahedral map (a uint32) and the map as RGBA32F; and translucency.bin, frame 2's
 * translucency mask as R32F, its motion as RG32F and its colour before the translucency as
 * RGBA32F. The program creates a FULL context with
 * every create-time chained struct, submits frames 0 and 2 with their shadow input (frame 2
 * also with the sun, the sky and its translucency), and extrapolates: frame 1 with diagnostics; frame 3 three times, once per warp kind, with
 * segmentation and network settings, both diagnostics and, last, an A2B10G10R10 output; then
 * frame 3 once more with its own shadow mask as the target shadow input. It
 * writes each output image and both frames' statistics to OUT_DIR, and exits 0 only when every
 * call did what the header says and validation reported nothing.
 */
#include "engine.h"

static void write_image(Image *image, const char *dir, const char *name) {
  size_t size = (size_t)width * height * image->texel_bytes;
  unsigned char *bytes = malloc(size);
  if (!bytes) exit(2);
  read_image(image, bytes);
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.bin", dir, name);
  FILE *file = fopen(path, "wb");
  if (!file || fwrite(bytes, 1, size, file) != size) {
    fprintf(stderr, "cannot write %s\n", path);
    exit(2);
  }
  fclose(file);
  free(bytes);
}

/* One instant's G-buffers, as engine images. */
typedef struct Frame {
  PatchexCamera camera;
  Image color, base_color, material, normal, color_without_dynamic_shadows;
  Image depth, shadow_mask, static_visibility, motion, stencil;
} Frame;

static Frame load_frame(const char *dir, int index) {
  char path[4096];
  snprintf(path, sizeof path, "%s/frame%d.bin", dir, index);
  FILE *file = fopen(path, "rb");
  if (!file) {
    fprintf(stderr, "cannot open %s\n", path);
    exit(2);
  }
  size_t pixels = (size_t)width * height;
  size_t size = sizeof(PatchexCamera) + pixels * (5 * 16 + 3 * 4 + 8 + 1);
  unsigned char *bytes = malloc(size);
  if (!bytes || fread(bytes, 1, size, file) != size) {
    fprintf(stderr, "%s is not %zu bytes\n", path, size);
    exit(2);
  }
  fclose(file);
  Frame f;
  const unsigned char *at = bytes;
  memcpy(&f.camera, at, sizeof f.camera);
  at += sizeof f.camera;
  Image *rgba[] = {&f.color, &f.base_color, &f.material, &f.normal,
                   &f.color_without_dynamic_shadows};
  for (size_t i = 0; i < sizeof rgba / sizeof rgba[0]; ++i, at += pixels * 16)
    *rgba[i] = input_image(VK_FORMAT_R32G32B32A32_SFLOAT, 16, at);
  f.depth = input_image(VK_FORMAT_R32_SFLOAT, 4, at);
  at += pixels * 4;
  f.shadow_mask = input_image(VK_FORMAT_R32_SFLOAT, 4, at);
  at += pixels * 4;
  f.static_visibility = input_image(VK_FORMAT_R32_SFLOAT, 4, at);
  at += pixels * 4;
  f.motion = input_image(VK_FORMAT_R32G32_SFLOAT, 8, at);
  at += pixels * 8;
  f.stencil = input_image(VK_FORMAT_R8_UINT, 1, at);
  free(bytes);
  return f;
}

static void destroy_frame(Frame *f) {
  Image *all[] = {&f->color, &f->base_color, &f->material, &f->normal,
                  &f->color_without_dynamic_shadows, &f->depth, &f->shadow_mask,
                  &f->static_visibility, &f->motion, &f->stencil};
  for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i) destroy_image(all[i]);
}

static PatchexGeometry geometry(const Frame *f) {
  PatchexGeometry g;
  memset(&g, 0, sizeof g);
  g.depth = describe(&f->depth);
  g.normal = describe(&f->normal);
  g.normal_encoding = PATCHEX_NORMAL_SIGNED;
  g.stencil = describe(&f->stencil);
  g.motion_vectors = describe(&f->motion);
  g.motion_vector_scale[0] = g.motion_vector_scale[1] = 1.0f;
  g.camera = f->camera;
  return g;
}

/* Frame `f` as frame `index`, with its shadow input, and optionally flow settings, the sun
   (direction, then illuminance) with the sky's map, and a translucency mask, motion and colour
   before the translucency (`translucency[0]`, `[1]`, `[2]`). */
static void submit(PatchexContext *ctx, const Frame *f, uint64_t index,
                   const PatchexShadowFlowSettings *flow, const float *sun, const Image *sky,
                   const Image *translucency) {
  PatchexShadowInput shadow;
  shadow.header = header(PATCHEX_STRUCT_TYPE_SHADOW_INPUT, sizeof shadow, flow);
  shadow.mask = describe(&f->shadow_mask);
  shadow.color_without_dynamic_shadows = describe(&f->color_without_dynamic_shadows);
  PatchexSkyLight reflected;
  reflected.header = header(PATCHEX_STRUCT_TYPE_SKY_LIGHT, sizeof reflected, &shadow);
  if (sky) {
    reflected.radiance = describe(sky);
    reflected.mip_levels = 1;
  }
  PatchexSunLight light;
  light.header = header(PATCHEX_STRUCT_TYPE_SUN_LIGHT, sizeof light,
                        sky ? (const void *)&reflected : &shadow);
  if (sun) {
    memcpy(light.direction, sun, sizeof light.direction);
    memcpy(light.illuminance, sun + 3, sizeof light.illuminance);
    /* With a shadow input: the visibility through static casters. */
    light.visibility = describe(&f->static_visibility);
  }
  const void *chain = sun ? (const void *)&light : &shadow;
  PatchexTranslucencyInput over;
  over.header = header(PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT, sizeof over, chain);
  if (translucency) {
    over.mask = describe(&translucency[0]);
    over.motion_vectors = describe(&translucency[1]);
    over.motion_vector_scale[0] = over.motion_vector_scale[1] = 1.0f;
    over.opaque_color = describe(&translucency[2]);
    chain = &over;
  }
  PatchexFrameDesc desc;
  memset(&desc, 0, sizeof desc);
  desc.header = header(PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof desc, chain);
  desc.frame_index = index;
  desc.queue_family_index = gpu.family;
  desc.width = width;
  desc.height = height;
  desc.color = describe(&f->color);
  desc.base_color = describe(&f->base_color);
  desc.material = describe(&f->material);
  desc.geometry = geometry(f);
  expect(patchex_submit_gbuffers(ctx, gpu.cmd, &desc), PATCHEX_RESULT_SUCCESS,
         "patchex_submit_gbuffers", ctx);
}

static PatchexExtrapolateDesc extrapolate_desc(const Frame *target, const Image *output,
                                               const void *chain) {
  PatchexExtrapolateDesc desc;
  memset(&desc, 0, sizeof desc);
  desc.header = header(PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof desc, chain);
  desc.queue_family_index = gpu.family;
  desc.alpha = 0.5f;
  desc.width = width;
  desc.height = height;
  desc.base_color = describe(&target->base_color);
  desc.material = describe(&target->material);
  desc.geometry = geometry(target);
  desc.output = describe(output);
  return desc;
}

static void write_stats(PatchexContext *ctx, uint64_t index, const char *dir, const char *name) {
  PatchexFrameStats stats;
  memset(&stats, 0, sizeof stats);
  stats.header = header(PATCHEX_STRUCT_TYPE_FRAME_STATS, sizeof stats, NULL);
  expect(patchex_get_frame_stats(ctx, index, &stats), PATCHEX_RESULT_SUCCESS,
         "patchex_get_frame_stats", ctx);
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.bin", dir, name);
  FILE *file = fopen(path, "wb");
  if (!file || fwrite(&stats, sizeof stats, 1, file) != 1) {
    fprintf(stderr, "cannot write %s\n", path);
    exit(2);
  }
  fclose(file);
}

int main(int argc, char **argv) {
  if (argc != 7) {
    fprintf(stderr, "usage: %s DATA_DIR OUT_DIR WIDTH HEIGHT FI_WEIGHTS NEAR_BE_WEIGHTS\n",
            argv[0]);
    return 2;
  }
  const char *data = argv[1], *out = argv[2];
  width = (uint32_t)atoi(argv[3]);
  height = (uint32_t)atoi(argv[4]);
  if (patchex_abi_version() != PATCHEX_ABI_VERSION) {
    fprintf(stderr, "library ABI %u, header ABI %u\n", patchex_abi_version(),
            PATCHEX_ABI_VERSION);
    return 1;
  }
  create_gpu();

  /* Every struct a create info takes, chained. Tensors for patches up to 64 texels a side: the
     whole-frame extrapolation runs at half the frame's resolution. */
  PatchexNetworkMemory memory;
  memory.header = header(PATCHEX_STRUCT_TYPE_NETWORK_MEMORY, sizeof memory, NULL);
  memory.max_patch_side = 64;
  PatchexNetworkPrecision precision;
  precision.header = header(PATCHEX_STRUCT_TYPE_NETWORK_PRECISION, sizeof precision, &memory);
  precision.tensors = PATCHEX_TENSOR_PRECISION_FP32;
  PatchexNetworkSettings networks;
  networks.header = header(PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS, sizeof networks, &precision);
  networks.run_fi = 1;
  networks.run_near_be = 1;
  networks.whole_frame = 0;
  networks.resolution_divisor = 1;
  networks.correct_valid_pixels = 1;
  PatchexNetworkWeights weights;
  weights.header = header(PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS, sizeof weights, &networks);
  weights.fi_path = argv[5];
  weights.near_be_path = argv[6];
  PatchexShadowFlowSettings flow;
  flow.header = header(PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS, sizeof flow, &weights);
  flow.levels = PATCHEX_DEFAULT_FLOW_LEVELS;
  flow.iterations = PATCHEX_DEFAULT_FLOW_ITERATIONS;
  flow.window_radius = PATCHEX_DEFAULT_FLOW_WINDOW_RADIUS;
  flow.poly_radius = PATCHEX_DEFAULT_FLOW_POLY_RADIUS;
  flow.poly_sigma = PATCHEX_DEFAULT_FLOW_POLY_SIGMA;
  PatchexSegmentationSettings segmentation;
  segmentation.header =
      header(PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS, sizeof segmentation, &flow);
  segmentation.growth_x = 2.5f;
  segmentation.growth_y = 3.5f;
  PatchexWarpSettings warp;
  warp.header = header(PATCHEX_STRUCT_TYPE_WARP_SETTINGS, sizeof warp, &segmentation);
  warp.kind = PATCHEX_WARP_GBUFFER_GUIDED;
  warp.kernel_radius = PATCHEX_DEFAULT_KERNEL_RADIUS;
  warp.sigma_spatial = PATCHEX_DEFAULT_SIGMA_SPATIAL;
  warp.sigma_depth = PATCHEX_DEFAULT_SIGMA_DEPTH;
  warp.sigma_normal = PATCHEX_DEFAULT_SIGMA_NORMAL;
  warp.sigma_position = PATCHEX_DEFAULT_SIGMA_POSITION;
  warp.occlusion_search_radius = PATCHEX_DEFAULT_OCCLUSION_SEARCH_RADIUS;
  warp.hole_fill = PATCHEX_HOLE_FILL_BACKGROUND;
  warp.resample = PATCHEX_RESAMPLE_CATMULL_ROM;

  PatchexCreateInfo info = create_info(PATCHEX_PRESET_FULL, 2, &warp);

  /* A failed create leaves *out_context as it was and says why on this thread. */
  PatchexContext *ctx = (PatchexContext *)&info;
  PatchexCreateInfo bad = info;
  bad.preset = 99;
  expect(patchex_create(&bad, &ctx), PATCHEX_RESULT_ERROR_INVALID_ARGUMENT, "bad create", NULL);
  if (ctx != (PatchexContext *)&info || patchex_last_error(NULL)[0] == '\0') {
    fprintf(stderr, "a failed patchex_create wrote *out_context or left no message\n");
    ++failures;
  }
  ctx = NULL;
  if (patchex_create(&info, &ctx) != PATCHEX_RESULT_SUCCESS) {
    fprintf(stderr, "patchex_create: %s\n", patchex_last_error(NULL));
    return 1;
  }

  Frame frames[4];
  for (int i = 0; i < 4; ++i) frames[i] = load_frame(data, i);
  float sun[6];
  char sun_path[4096];
  snprintf(sun_path, sizeof sun_path, "%s/sun.bin", data);
  FILE *sun_file = fopen(sun_path, "rb");
  if (!sun_file || fread(sun, sizeof sun, 1, sun_file) != 1) {
    fprintf(stderr, "cannot read %s\n", sun_path);
    return 2;
  }
  fclose(sun_file);
  char sky_path[4096];
  snprintf(sky_path, sizeof sky_path, "%s/sky.bin", data);
  FILE *sky_file = fopen(sky_path, "rb");
  uint32_t sky_side = 0;
  if (!sky_file || fread(&sky_side, sizeof sky_side, 1, sky_file) != 1 || sky_side == 0) {
    fprintf(stderr, "cannot read %s\n", sky_path);
    return 2;
  }
  size_t sky_size = (size_t)sky_side * sky_side * 16;
  unsigned char *sky_bytes = malloc(sky_size);
  if (!sky_bytes || fread(sky_bytes, sky_size, 1, sky_file) != 1) {
    fprintf(stderr, "cannot read %s\n", sky_path);
    return 2;
  }
  fclose(sky_file);
  Image sky = input_image_sized(VK_FORMAT_R32G32B32A32_SFLOAT, 16, sky_side, sky_side, sky_bytes);
  free(sky_bytes);
  char translucency_path[4096];
  snprintf(translucency_path, sizeof translucency_path, "%s/translucency.bin", data);
  FILE *translucency_file = fopen(translucency_path, "rb");
  size_t pixels = (size_t)width * height;
  unsigned char *translucency_bytes = malloc(pixels * 28);
  if (!translucency_file || !translucency_bytes ||
      fread(translucency_bytes, pixels * 28, 1, translucency_file) != 1) {
    fprintf(stderr, "cannot read %s\n", translucency_path);
    return 2;
  }
  fclose(translucency_file);
  Image translucency[3] = {
      input_image(VK_FORMAT_R32_SFLOAT, 4, translucency_bytes),
      input_image(VK_FORMAT_R32G32_SFLOAT, 8, translucency_bytes + pixels * 4),
      input_image(VK_FORMAT_R32G32B32A32_SFLOAT, 16, translucency_bytes + pixels * 12)};
  free(translucency_bytes);
  const VkImageUsageFlags storage = VK_IMAGE_USAGE_STORAGE_BIT;
  Image first = output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage);
  Image first_diagnostics = output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage);
  Image outputs[3] = {output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage),
                      output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage),
                      /* Packed formats are copied in: TRANSFER_DST usage, no STORAGE. */
                      output_image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, 4,
                                   VK_IMAGE_USAGE_SAMPLED_BIT)};
  Image diagnostics = output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage);
  Image shadow_diagnostics = output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage);
  Image target_shadows = output_image(VK_FORMAT_R16G16B16A16_SFLOAT, 8, storage);

  /* Frame t-1 (index 1) and its halfway instant, with a flow override on the frame. */
  PatchexShadowFlowSettings frame_flow = flow;
  frame_flow.header.next = NULL;
  frame_flow.iterations = 2;
  begin();
  submit(ctx, &frames[0], 1, &frame_flow, NULL, NULL, NULL);
  PatchexDiagnostics first_diag;
  first_diag.header = header(PATCHEX_STRUCT_TYPE_DIAGNOSTICS, sizeof first_diag, NULL);
  first_diag.image = describe(&first_diagnostics);
  PatchexExtrapolateDesc desc = extrapolate_desc(&frames[1], &first, &first_diag);
  expect(patchex_extrapolate(ctx, gpu.cmd, &desc), PATCHEX_RESULT_SUCCESS, "extrapolate 1", ctx);
  submit_and_wait();

  /* Frame t (index 2), with the sun, the sky and its translucency: three extrapolations of its
     halfway instant, one per warp. */
  begin();
  submit(ctx, &frames[2], 2, NULL, sun, &sky, translucency);

  const PatchexWarpKind kinds[3] = {PATCHEX_WARP_GBUFFER_GUIDED, PATCHEX_WARP_MOTION_VECTOR,
                                    PATCHEX_WARP_OCCLUSION_MOTION_VECTOR};
  for (int k = 0; k < 3; ++k) {
    PatchexNetworkSettings run;
    run.header = header(PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS, sizeof run, NULL);
    run.run_fi = 1;
    run.run_near_be = k == 0;
    run.whole_frame = k == 2;
    run.resolution_divisor = k == 1 ? 2 : 1;
    run.correct_valid_pixels = k == 1;
    PatchexSegmentationSettings growth;
    growth.header = header(PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS, sizeof growth, &run);
    growth.growth_x = 3.0f;
    growth.growth_y = 1.5f;
    PatchexWarpSettings kind = warp;
    kind.header = header(PATCHEX_STRUCT_TYPE_WARP_SETTINGS, sizeof kind, &growth);
    kind.kind = kinds[k];
    PatchexShadowDiagnostics shadow_diag;
    shadow_diag.header = header(PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS, sizeof shadow_diag, &kind);
    shadow_diag.image = describe(&shadow_diagnostics);
    PatchexDiagnostics diag;
    diag.header = header(PATCHEX_STRUCT_TYPE_DIAGNOSTICS, sizeof diag, &shadow_diag);
    diag.image = describe(&diagnostics);
    desc = extrapolate_desc(&frames[3], &outputs[k], k == 0 ? (const void *)&diag : &kind);
    expect(patchex_extrapolate(ctx, gpu.cmd, &desc), PATCHEX_RESULT_SUCCESS, "extrapolate 2", ctx);
  }

  /* The fourth: the shadows at the target from the target's own mask. */
  PatchexTargetShadowInput target_mask;
  target_mask.header = header(PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT, sizeof target_mask, NULL);
  target_mask.mask = describe(&frames[3].shadow_mask);
  desc = extrapolate_desc(&frames[3], &target_shadows, &target_mask);
  expect(patchex_extrapolate(ctx, gpu.cmd, &desc), PATCHEX_RESULT_SUCCESS,
         "extrapolate with the target's shadow mask", ctx);

  /* A refused call records nothing and names its fault. */
  PatchexStructHeader unknown = header(999, sizeof unknown, NULL);
  desc = extrapolate_desc(&frames[3], &first, &unknown);
  expect(patchex_extrapolate(ctx, gpu.cmd, &desc), PATCHEX_RESULT_ERROR_INVALID_STRUCT_TYPE,
         "a chain with an unknown struct", ctx);
  if (patchex_last_error(ctx)[0] == '\0') {
    fprintf(stderr, "a refused call left no message\n");
    ++failures;
  }
  submit_and_wait();

  write_stats(ctx, 1, out, "stats1");
  write_stats(ctx, 2, out, "stats2");
  write_image(&first, out, "first");
  write_image(&first_diagnostics, out, "first_diagnostics");
  write_image(&outputs[0], out, "gbuffer_guided");
  write_image(&outputs[1], out, "motion_vector");
  write_image(&outputs[2], out, "occlusion_motion_vector");
  write_image(&diagnostics, out, "diagnostics");
  write_image(&shadow_diagnostics, out, "shadow_diagnostics");
  write_image(&target_shadows, out, "target_shadows");

  CHECK(vkDeviceWaitIdle(gpu.device));
  patchex_destroy(ctx);
  for (int i = 0; i < 4; ++i) destroy_frame(&frames[i]);
  destroy_image(&translucency[0]);
  destroy_image(&translucency[1]);
  destroy_image(&translucency[2]);
  destroy_image(&sky);
  Image *images[] = {&first, &first_diagnostics, &outputs[0], &outputs[1], &outputs[2],
                     &diagnostics, &shadow_diagnostics, &target_shadows};
  for (size_t i = 0; i < sizeof images / sizeof images[0]; ++i) destroy_image(images[i]);
  destroy_gpu();
  return verdict();
}
