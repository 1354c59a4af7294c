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
 * material, normal and colour without dynamic shadows as RGBA32F, depth and shadow mask as
 * R32F, motion vectors as RG32F and stencil ids as R8_UINT. The program creates a FULL context
 * with every create-time chained struct, submits frames 0 and 2 with their shadow input, and
 * extrapolates: frame 1 with diagnostics; frame 3 three times, once per warp kind, with
 * segmentation and network settings, both diagnostics and, last, an A2B10G10R10 output. It
 * writes each output image and both frames' statistics to OUT_DIR, and exits 0 only when every
 * call did what the header says and validation reported nothing.
 */
#include <patchex.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CHECK(call)                                                           \
  do {                                                                        \
    VkResult check_result_ = (call);                                          \
    if (check_result_ != VK_SUCCESS) {                                        \
      fprintf(stderr, "%s:%d: %s failed: %d\n", __FILE__, __LINE__, #call,     \
              (int)check_result_);                                            \
      exit(2);                                                                \
    }                                                                         \
  } while (0)

static int validation_messages = 0;
static int failures = 0;

static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT type,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
  (void)severity;
  (void)type;
  (void)user;
  fprintf(stderr, "validation: %s\n", data->pMessage);
  ++validation_messages;
  return VK_FALSE;
}

static void on_log(void *user, PatchexLogLevel level, const char *message) {
  (void)user;
  fprintf(stderr, "patchex log %u: %s\n", level, message);
}

/* A patchex call that must return `want`. */
static void expect(PatchexResult got, PatchexResult want, const char *what, PatchexContext *ctx) {
  if (got != want) {
    fprintf(stderr, "%s returned %d (%s), expected %d: %s\n", what, (int)got,
            patchex_result_string(got), (int)want, patchex_last_error(ctx));
    ++failures;
  }
}

typedef struct Gpu {
  VkInstance instance;
  VkDebugUtilsMessengerEXT messenger;
  VkPhysicalDevice physical_device;
  VkDevice device;
  VkQueue queue;
  uint32_t family;
  VkCommandPool pool;
  VkCommandBuffer cmd;
  VkFence fence;
} Gpu;

static Gpu gpu;

static void create_gpu(void) {
  VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "patchex C11 ABI test";
  app.apiVersion = VK_API_VERSION_1_1;
  const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
  const char *extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME,
                              VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  VkValidationFeatureEnableEXT enables[] = {
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features = {.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkInstanceCreateInfo info = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = &features;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = 1;
  info.ppEnabledLayerNames = layers;
  info.enabledExtensionCount = 2;
  info.ppEnabledExtensionNames = extensions;
  CHECK(vkCreateInstance(&info, NULL, &gpu.instance));

  VkDebugUtilsMessengerCreateInfoEXT messenger = {
      .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = on_validation;
  PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
      (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
          gpu.instance, "vkCreateDebugUtilsMessengerEXT");
  CHECK(create_messenger(gpu.instance, &messenger, NULL, &gpu.messenger));

  uint32_t count = 1;
  vkEnumeratePhysicalDevices(gpu.instance, &count, &gpu.physical_device);
  if (count == 0) {
    fprintf(stderr, "no Vulkan device\n");
    exit(2);
  }
  uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(gpu.physical_device, &families, NULL);
  VkQueueFamilyProperties properties[16];
  families = families > 16 ? 16 : families;
  vkGetPhysicalDeviceQueueFamilyProperties(gpu.physical_device, &families, properties);
  for (gpu.family = 0; gpu.family < families; ++gpu.family)
    if (properties[gpu.family].queueFlags & VK_QUEUE_COMPUTE_BIT) break;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = gpu.family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue;
  CHECK(vkCreateDevice(gpu.physical_device, &device_info, NULL, &gpu.device));
  vkGetDeviceQueue(gpu.device, gpu.family, 0, &gpu.queue);

  VkCommandPoolCreateInfo pool = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = gpu.family;
  CHECK(vkCreateCommandPool(gpu.device, &pool, NULL, &gpu.pool));
  VkCommandBufferAllocateInfo cmd = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cmd.commandPool = gpu.pool;
  cmd.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cmd.commandBufferCount = 1;
  CHECK(vkAllocateCommandBuffers(gpu.device, &cmd, &gpu.cmd));
  VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  CHECK(vkCreateFence(gpu.device, &fence, NULL, &gpu.fence));
}

static void begin(void) {
  VkCommandBufferBeginInfo info = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  CHECK(vkBeginCommandBuffer(gpu.cmd, &info));
}

static void submit_and_wait(void) {
  CHECK(vkEndCommandBuffer(gpu.cmd));
  VkSubmitInfo submit = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &gpu.cmd;
  CHECK(vkQueueSubmit(gpu.queue, 1, &submit, gpu.fence));
  CHECK(vkWaitForFences(gpu.device, 1, &gpu.fence, VK_TRUE, UINT64_MAX));
  CHECK(vkResetFences(gpu.device, 1, &gpu.fence));
}

static uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags flags) {
  VkPhysicalDeviceMemoryProperties properties;
  vkGetPhysicalDeviceMemoryProperties(gpu.physical_device, &properties);
  for (uint32_t i = 0; i < properties.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (properties.memoryTypes[i].propertyFlags & flags) == flags) return i;
  fprintf(stderr, "no suitable memory type\n");
  exit(2);
}

static VkDeviceMemory allocate(VkMemoryRequirements requirements, VkMemoryPropertyFlags flags) {
  VkMemoryAllocateInfo info = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = memory_type(requirements.memoryTypeBits, flags);
  VkDeviceMemory memory;
  CHECK(vkAllocateMemory(gpu.device, &info, NULL, &memory));
  return memory;
}

/* An engine image and the layout it is kept in between calls. */
typedef struct Image {
  VkImage image;
  VkImageView view;
  VkDeviceMemory memory;
  VkFormat format;
  VkImageUsageFlags usage;
  VkImageLayout layout;
  uint32_t texel_bytes;
} Image;

static uint32_t width, height;

static Image create_image(VkFormat format, uint32_t texel_bytes, VkImageUsageFlags usage) {
  Image image = {0};
  image.format = format;
  image.texel_bytes = texel_bytes;
  image.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  image.layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImageCreateInfo info = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent.width = width;
  info.extent.height = height;
  info.extent.depth = 1;
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = image.usage;
  CHECK(vkCreateImage(gpu.device, &info, NULL, &image.image));
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(gpu.device, image.image, &requirements);
  image.memory = allocate(requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  CHECK(vkBindImageMemory(gpu.device, image.image, image.memory, 0));
  VkImageViewCreateInfo view = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = image.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
  view.subresourceRange.levelCount = 1;
  view.subresourceRange.layerCount = 1;
  CHECK(vkCreateImageView(gpu.device, &view, NULL, &image.view));
  return image;
}

static void destroy_image(Image *image) {
  vkDestroyImageView(gpu.device, image->view, NULL);
  vkDestroyImage(gpu.device, image->image, NULL);
  vkFreeMemory(gpu.device, image->memory, NULL);
}

static void transition(Image *image, VkImageLayout layout) {
  VkImageMemoryBarrier barrier = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  barrier.oldLayout = image->layout;
  barrier.newLayout = layout;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image->image;
  barrier.subresourceRange.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
  barrier.subresourceRange.levelCount = 1;
  barrier.subresourceRange.layerCount = 1;
  vkCmdPipelineBarrier(gpu.cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 1, &barrier);
  image->layout = layout;
}

typedef struct Buffer {
  VkBuffer buffer;
  VkDeviceMemory memory;
  void *mapped;
} Buffer;

static Buffer create_buffer(VkDeviceSize size) {
  Buffer b;
  VkBufferCreateInfo info = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  CHECK(vkCreateBuffer(gpu.device, &info, NULL, &b.buffer));
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(gpu.device, b.buffer, &requirements);
  b.memory = allocate(requirements, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                        VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  CHECK(vkBindBufferMemory(gpu.device, b.buffer, b.memory, 0));
  CHECK(vkMapMemory(gpu.device, b.memory, 0, size, 0, &b.mapped));
  return b;
}

static void destroy_buffer(Buffer *b) {
  vkDestroyBuffer(gpu.device, b->buffer, NULL);
  vkFreeMemory(gpu.device, b->memory, NULL);
}

static VkBufferImageCopy whole_image(void) {
  VkBufferImageCopy copy;
  memset(&copy, 0, sizeof copy);
  copy.imageSubresource.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
  copy.imageSubresource.layerCount = 1;
  copy.imageExtent.width = width;
  copy.imageExtent.height = height;
  copy.imageExtent.depth = 1;
  return copy;
}

/* An input image filled from `bytes` and left in SHADER_READ_ONLY_OPTIMAL. */
static Image input_image(VkFormat format, uint32_t texel_bytes, const unsigned char *bytes) {
  Image image = create_image(format, texel_bytes, VK_IMAGE_USAGE_SAMPLED_BIT);
  size_t size = (size_t)width * height * texel_bytes;
  Buffer staging = create_buffer(size);
  memcpy(staging.mapped, bytes, size);
  begin();
  transition(&image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  VkBufferImageCopy copy = whole_image();
  vkCmdCopyBufferToImage(gpu.cmd, staging.buffer, image.image,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  transition(&image, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  submit_and_wait();
  destroy_buffer(&staging);
  return image;
}

/* An image patchex writes, kept in GENERAL. */
static Image output_image(VkFormat format, uint32_t texel_bytes, VkImageUsageFlags usage) {
  Image image = create_image(format, texel_bytes, usage);
  begin();
  transition(&image, VK_IMAGE_LAYOUT_GENERAL);
  submit_and_wait();
  return image;
}

static void write_image(Image *image, const char *dir, const char *name) {
  size_t size = (size_t)width * height * image->texel_bytes;
  Buffer staging = create_buffer(size);
  begin();
  VkImageLayout kept = image->layout;
  transition(image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  VkBufferImageCopy copy = whole_image();
  vkCmdCopyImageToBuffer(gpu.cmd, image->image, image->layout, staging.buffer, 1, &copy);
  transition(image, kept);
  VkMemoryBarrier to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(gpu.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &to_host, 0, NULL, 0, NULL);
  submit_and_wait();
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.bin", dir, name);
  FILE *file = fopen(path, "wb");
  if (!file || fwrite(staging.mapped, 1, size, file) != size) {
    fprintf(stderr, "cannot write %s\n", path);
    exit(2);
  }
  fclose(file);
  destroy_buffer(&staging);
}

static PatchexImage describe(const Image *image) {
  PatchexImage d;
  d.image = image->image;
  d.view = image->view;
  d.format = image->format;
  d.width = width;
  d.height = height;
  d.layout = image->layout;
  d.usage = image->usage;
  return d;
}

/* One instant's G-buffers, as engine images. */
typedef struct Frame {
  PatchexCamera camera;
  Image color, base_color, material, normal, color_without_dynamic_shadows;
  Image depth, shadow_mask, motion, stencil;
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
  size_t size = sizeof(PatchexCamera) + pixels * (5 * 16 + 4 + 4 + 8 + 1);
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
  f.motion = input_image(VK_FORMAT_R32G32_SFLOAT, 8, at);
  at += pixels * 8;
  f.stencil = input_image(VK_FORMAT_R8_UINT, 1, at);
  free(bytes);
  return f;
}

static void destroy_frame(Frame *f) {
  Image *all[] = {&f->color, &f->base_color, &f->material, &f->normal,
                  &f->color_without_dynamic_shadows, &f->depth, &f->shadow_mask, &f->motion,
                  &f->stencil};
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

static PatchexStructHeader header(PatchexStructType type, uint32_t size, const void *next) {
  PatchexStructHeader h;
  h.struct_type = type;
  h.struct_size = size;
  h.next = next;
  return h;
}

/* Frame `f` as frame `index`, with its shadow input and (optionally) flow settings. */
static void submit(PatchexContext *ctx, const Frame *f, uint64_t index,
                   const PatchexShadowFlowSettings *flow) {
  PatchexShadowInput shadow;
  shadow.header = header(PATCHEX_STRUCT_TYPE_SHADOW_INPUT, sizeof shadow, flow);
  shadow.mask = describe(&f->shadow_mask);
  shadow.color_without_dynamic_shadows = describe(&f->color_without_dynamic_shadows);
  PatchexFrameDesc desc;
  memset(&desc, 0, sizeof desc);
  desc.header = header(PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof desc, &shadow);
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

  PatchexCreateInfo info;
  memset(&info, 0, sizeof info);
  info.header = header(PATCHEX_STRUCT_TYPE_CREATE_INFO, sizeof info, &warp);
  info.instance = gpu.instance;
  info.physical_device = gpu.physical_device;
  info.device = gpu.device;
  info.get_instance_proc_addr = vkGetInstanceProcAddr;
  info.get_device_proc_addr = vkGetDeviceProcAddr;
  info.queue_family_index = gpu.family;
  info.max_width = width;
  info.max_height = height;
  info.frames_in_flight = 2;
  info.preset = PATCHEX_PRESET_FULL;
  info.log_callback = on_log;

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

  /* Frame t-1 (index 1) and its halfway instant, with a flow override on the frame. */
  PatchexShadowFlowSettings frame_flow = flow;
  frame_flow.header.next = NULL;
  frame_flow.iterations = 2;
  begin();
  submit(ctx, &frames[0], 1, &frame_flow);
  PatchexDiagnostics first_diag;
  first_diag.header = header(PATCHEX_STRUCT_TYPE_DIAGNOSTICS, sizeof first_diag, NULL);
  first_diag.image = describe(&first_diagnostics);
  PatchexExtrapolateDesc desc = extrapolate_desc(&frames[1], &first, &first_diag);
  expect(patchex_extrapolate(ctx, gpu.cmd, &desc), PATCHEX_RESULT_SUCCESS, "extrapolate 1", ctx);
  submit_and_wait();

  /* Frame t (index 2): three extrapolations of its halfway instant, one per warp. */
  begin();
  submit(ctx, &frames[2], 2, NULL);

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

  CHECK(vkDeviceWaitIdle(gpu.device));
  patchex_destroy(ctx);
  for (int i = 0; i < 4; ++i) destroy_frame(&frames[i]);
  Image *images[] = {&first, &first_diagnostics, &outputs[0], &outputs[1], &outputs[2],
                     &diagnostics, &shadow_diagnostics};
  for (size_t i = 0; i < sizeof images / sizeof images[0]; ++i) destroy_image(images[i]);
  vkDestroyFence(gpu.device, gpu.fence, NULL);
  vkDestroyCommandPool(gpu.device, gpu.pool, NULL);
  vkDestroyDevice(gpu.device, NULL);
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
      (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
          gpu.instance, "vkDestroyDebugUtilsMessengerEXT");
  destroy_messenger(gpu.instance, gpu.messenger, NULL);
  vkDestroyInstance(gpu.instance, NULL);

  printf("%s (%d failures, %d validation messages)\n",
         failures == 0 && validation_messages == 0 ? "ok" : "FAILED", failures,
         validation_messages);
  return failures == 0 && validation_messages == 0 ? 0 : 1;
}
