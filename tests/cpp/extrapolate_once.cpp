// A minimal C++17 "engine" that uses patchex exactly as a game engine would: through
// include/patchex.h and the shared library, on its own Vulkan instance, device, queue, command
// buffer, fence and images. It renders (on the CPU) a textured square moving over a shaded
// background, submits frame t, extrapolates the halfway instant, and compares the output with
// the instant rendered in full. Exit status 0 only when the result is right and the validation
// layer (with synchronization validation) reported nothing.

#include "patchex.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

constexpr uint32_t kWidth = 64;
constexpr uint32_t kHeight = 48;
constexpr int kSquareSize = 16;
constexpr int kSquareY = 16;
constexpr int kSquareXAtT = 12;
constexpr int kSquareStep = 2;  // pixels the square moves from frame t to the target

int g_validation_messages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void*) {
  std::fprintf(stderr, "validation: %s\n", data->pMessage);
  ++g_validation_messages;
  return VK_FALSE;
}

#define CHECK(call)                                                      \
  do {                                                                   \
    VkResult result_ = (call);                                           \
    if (result_ != VK_SUCCESS) {                                         \
      std::fprintf(stderr, "%s failed: %d\n", #call, (int)result_);      \
      std::exit(2);                                                      \
    }                                                                    \
  } while (0)

struct Engine {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkCommandPool pool = VK_NULL_HANDLE;

  uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const {
    VkPhysicalDeviceMemoryProperties properties;
    vkGetPhysicalDeviceMemoryProperties(physical_device, &properties);
    for (uint32_t i = 0; i < properties.memoryTypeCount; ++i)
      if ((bits & (1u << i)) && (properties.memoryTypes[i].propertyFlags & flags) == flags) return i;
    std::fprintf(stderr, "no suitable memory type\n");
    std::exit(2);
  }

  VkCommandBuffer begin() const {
    VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    info.commandPool = pool;
    info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    info.commandBufferCount = 1;
    VkCommandBuffer cmd;
    CHECK(vkAllocateCommandBuffers(device, &info, &cmd));
    VkCommandBufferBeginInfo begin_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin_info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    CHECK(vkBeginCommandBuffer(cmd, &begin_info));
    return cmd;
  }

  void submit_and_wait(VkCommandBuffer cmd) const {
    CHECK(vkEndCommandBuffer(cmd));
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    CHECK(vkCreateFence(device, &fence_info, nullptr, &fence));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    CHECK(vkQueueSubmit(queue, 1, &submit, fence));
    CHECK(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX));
    vkDestroyFence(device, fence, nullptr);
    vkFreeCommandBuffers(device, pool, 1, &cmd);
  }
};

Engine create_engine() {
  Engine e;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "patchex C++ engine test";
  app.apiVersion = VK_API_VERSION_1_2;
  const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = &features;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = 1;
  info.ppEnabledLayerNames = layers;
  info.enabledExtensionCount = 2;
  info.ppEnabledExtensionNames = extensions;
  CHECK(vkCreateInstance(&info, nullptr, &e.instance));

  VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
  messenger.pfnUserCallback = on_validation;
  auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(e.instance, "vkCreateDebugUtilsMessengerEXT"));
  CHECK(create_messenger(e.instance, &messenger, nullptr, &e.messenger));

  uint32_t count = 1;
  vkEnumeratePhysicalDevices(e.instance, &count, &e.physical_device);
  if (count == 0) {
    std::fprintf(stderr, "no Vulkan device\n");
    std::exit(2);
  }
  uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(e.physical_device, &families, nullptr);
  std::vector<VkQueueFamilyProperties> properties(families);
  vkGetPhysicalDeviceQueueFamilyProperties(e.physical_device, &families, properties.data());
  for (e.family = 0; e.family < families; ++e.family)
    if (properties[e.family].queueFlags & VK_QUEUE_COMPUTE_BIT) break;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = e.family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue;
  CHECK(vkCreateDevice(e.physical_device, &device_info, nullptr, &e.device));
  vkGetDeviceQueue(e.device, e.family, 0, &e.queue);
  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.queueFamilyIndex = e.family;
  CHECK(vkCreateCommandPool(e.device, &pool, nullptr, &e.pool));
  return e;
}

// An engine-owned image, uploaded once and kept in `layout` (SHADER_READ_ONLY_OPTIMAL here).
struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkImageUsageFlags usage = 0;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  uint32_t texel_bytes = 0;

  PatchexImage describe() const { return PatchexImage{image, view, format, kWidth, kHeight, layout, usage}; }
};

struct Buffer {
  VkBuffer buffer;
  VkDeviceMemory memory;
};

Buffer staging(const Engine& e, VkDeviceSize size) {
  Buffer b;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  CHECK(vkCreateBuffer(e.device, &info, nullptr, &b.buffer));
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(e.device, b.buffer, &requirements);
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = e.memory_type(requirements.memoryTypeBits,
                                           VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  CHECK(vkAllocateMemory(e.device, &allocate, nullptr, &b.memory));
  CHECK(vkBindBufferMemory(e.device, b.buffer, b.memory, 0));
  return b;
}

void transition(VkCommandBuffer cmd, const Image& image, VkImageLayout from, VkImageLayout to) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image.image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr,
                       0, nullptr, 1, &barrier);
}

VkBufferImageCopy whole_image() {
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {kWidth, kHeight, 1};
  return copy;
}

Image create_image(const Engine& e, VkFormat format, uint32_t texel_bytes, VkImageUsageFlags usage,
                   VkImageLayout layout, const void* texels) {
  Image image;
  image.format = format;
  image.usage = usage | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  image.layout = layout;
  image.texel_bytes = texel_bytes;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {kWidth, kHeight, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = image.usage;
  CHECK(vkCreateImage(e.device, &info, nullptr, &image.image));
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(e.device, image.image, &requirements);
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = e.memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  CHECK(vkAllocateMemory(e.device, &allocate, nullptr, &image.memory));
  CHECK(vkBindImageMemory(e.device, image.image, image.memory, 0));
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = image.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  CHECK(vkCreateImageView(e.device, &view, nullptr, &image.view));

  VkDeviceSize size = VkDeviceSize(kWidth) * kHeight * texel_bytes;
  Buffer upload = staging(e, size);
  void* mapped;
  CHECK(vkMapMemory(e.device, upload.memory, 0, size, 0, &mapped));
  std::memcpy(mapped, texels, size);
  vkUnmapMemory(e.device, upload.memory);
  VkCommandBuffer cmd = e.begin();
  transition(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  VkBufferImageCopy copy = whole_image();
  vkCmdCopyBufferToImage(cmd, upload.buffer, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  transition(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, layout);
  e.submit_and_wait(cmd);
  vkDestroyBuffer(e.device, upload.buffer, nullptr);
  vkFreeMemory(e.device, upload.memory, nullptr);
  return image;
}

std::vector<uint16_t> read_back(const Engine& e, const Image& image) {
  VkDeviceSize size = VkDeviceSize(kWidth) * kHeight * image.texel_bytes;
  Buffer download = staging(e, size);
  VkCommandBuffer cmd = e.begin();
  transition(cmd, image, image.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  VkBufferImageCopy copy = whole_image();
  vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, download.buffer, 1, &copy);
  transition(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image.layout);
  VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0,
                       nullptr, 0, nullptr);
  e.submit_and_wait(cmd);
  std::vector<uint16_t> halves(size / 2);
  void* mapped;
  CHECK(vkMapMemory(e.device, download.memory, 0, size, 0, &mapped));
  std::memcpy(halves.data(), mapped, size);
  vkUnmapMemory(e.device, download.memory);
  vkDestroyBuffer(e.device, download.buffer, nullptr);
  vkFreeMemory(e.device, download.memory, nullptr);
  return halves;
}

void destroy_image(const Engine& e, Image& image) {
  vkDestroyImageView(e.device, image.view, nullptr);
  vkDestroyImage(e.device, image.image, nullptr);
  vkFreeMemory(e.device, image.memory, nullptr);
}

float half_to_float(uint16_t h) {
  uint32_t sign = (h >> 15) & 1, exponent = (h >> 10) & 31, mantissa = h & 1023;
  float value = exponent == 0 ? std::ldexp(float(mantissa), -24)
                              : std::ldexp(float(mantissa | 1024), int(exponent) - 25);
  return sign ? -value : value;
}

// One instant of the scene: the square's left edge at `square_x`.
struct Frame {
  std::vector<float> color, base_color, normal, depth, motion;
  std::vector<uint8_t> stencil;
};

Frame render(int square_x, float motion_x) {
  Frame f;
  size_t pixels = size_t(kWidth) * kHeight;
  f.color.resize(pixels * 4);
  f.base_color.resize(pixels * 4);
  f.normal.resize(pixels * 4);
  f.depth.resize(pixels);
  f.motion.resize(pixels * 2);
  f.stencil.resize(pixels);
  for (uint32_t y = 0; y < kHeight; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      size_t i = size_t(y) * kWidth + x;
      int local_x = int(x) - square_x, local_y = int(y) - kSquareY;
      bool square = local_x >= 0 && local_x < kSquareSize && local_y >= 0 && local_y < kSquareSize;
      float base[3], shading;
      if (square) {
        bool check = ((local_x / 4) + (local_y / 4)) % 2 == 0;  // texture moves with the square
        base[0] = check ? 0.9f : 0.2f, base[1] = 0.3f, base[2] = check ? 0.2f : 0.8f;
        shading = 0.9f;
      } else {
        bool check = ((x / 8) + (y / 8)) % 2 == 0;
        base[0] = base[1] = base[2] = check ? 0.6f : 0.3f;
        shading = 0.4f + 0.5f * float(x) / kWidth;
      }
      float modulation = 0.08f * 0.5f;  // specular 0.5, metallic 0 (no material image)
      for (int c = 0; c < 3; ++c) {
        f.base_color[i * 4 + c] = base[c];
        f.color[i * 4 + c] = (base[c] + modulation) * shading;
      }
      f.base_color[i * 4 + 3] = f.color[i * 4 + 3] = 1.0f;
      f.normal[i * 4 + 2] = 1.0f;  // facing the camera
      f.depth[i] = square ? 0.5f : 0.9f;
      f.stencil[i] = square ? 1 : 0;
      f.motion[i * 2] = square ? motion_x : 0.0f;
    }
  }
  return f;
}

struct GpuFrame {
  Image color, base_color, normal, depth, stencil, motion;
};

GpuFrame upload(const Engine& e, const Frame& f) {
  const VkImageUsageFlags sampled = VK_IMAGE_USAGE_SAMPLED_BIT;
  const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  return GpuFrame{
      create_image(e, VK_FORMAT_R32G32B32A32_SFLOAT, 16, sampled, read, f.color.data()),
      create_image(e, VK_FORMAT_R32G32B32A32_SFLOAT, 16, sampled, read, f.base_color.data()),
      create_image(e, VK_FORMAT_R32G32B32A32_SFLOAT, 16, sampled, read, f.normal.data()),
      create_image(e, VK_FORMAT_R32_SFLOAT, 4, sampled, read, f.depth.data()),
      create_image(e, VK_FORMAT_R8_UINT, 1, sampled, read, f.stencil.data()),
      create_image(e, VK_FORMAT_R32G32_SFLOAT, 8, sampled, read, f.motion.data()),
  };
}

PatchexCamera camera() {
  // A camera at the origin looking down -z, with a Vulkan-style perspective (y down, depth 0..1).
  PatchexCamera c{};
  for (int i = 0; i < 4; ++i) c.view[i * 5] = 1.0f;
  const float near_plane = 0.1f, far_plane = 100.0f, f = 1.0f / std::tan(0.5f);
  const float aspect = float(kWidth) / kHeight;
  c.projection[0] = f / aspect;
  c.projection[5] = -f;
  c.projection[10] = far_plane / (near_plane - far_plane);
  c.projection[11] = -1.0f;
  c.projection[14] = near_plane * far_plane / (near_plane - far_plane);
  c.near = near_plane;
  c.far = far_plane;
  c.depth_convention = PATCHEX_DEPTH_HARDWARE;
  return c;
}

PatchexGeometry geometry(const GpuFrame& g) {
  PatchexGeometry geo{};
  geo.depth = g.depth.describe();
  geo.normal = g.normal.describe();
  geo.normal_encoding = PATCHEX_NORMAL_SIGNED;
  geo.stencil = g.stencil.describe();
  geo.motion_vectors = g.motion.describe();
  geo.motion_vector_scale[0] = geo.motion_vector_scale[1] = 1.0f;
  geo.camera = camera();
  return geo;
}

void destroy_frame(const Engine& e, GpuFrame& g) {
  for (Image* image : {&g.color, &g.base_color, &g.normal, &g.depth, &g.stencil, &g.motion}) destroy_image(e, *image);
}

}  // namespace

int main() {
  std::printf("patchex ABI version %u\n", patchex_abi_version());
  Engine e = create_engine();

  PatchexCreateInfo info{};
  info.header = {PATCHEX_STRUCT_TYPE_CREATE_INFO, sizeof(PatchexCreateInfo), nullptr};
  info.instance = e.instance;
  info.physical_device = e.physical_device;
  info.device = e.device;
  info.get_instance_proc_addr = vkGetInstanceProcAddr;
  info.get_device_proc_addr = vkGetDeviceProcAddr;
  info.queue_family_index = e.family;
  info.max_width = kWidth;
  info.max_height = kHeight;
  info.frames_in_flight = 2;
  info.preset = PATCHEX_PRESET_WARP_ONLY;
  PatchexContext* context = nullptr;
  if (patchex_create(&info, &context) != PATCHEX_RESULT_SUCCESS) {
    std::fprintf(stderr, "patchex_create: %s\n", patchex_last_error(nullptr));
    return 1;
  }

  Frame source = render(kSquareXAtT, 0.0f);
  Frame target = render(kSquareXAtT + kSquareStep, -float(kSquareStep));
  GpuFrame gpu_source = upload(e, source), gpu_target = upload(e, target);
  std::vector<uint16_t> zeros(size_t(kWidth) * kHeight * 4, 0);
  Image output = create_image(e, VK_FORMAT_R16G16B16A16_SFLOAT, 8, VK_IMAGE_USAGE_STORAGE_BIT,
                              VK_IMAGE_LAYOUT_GENERAL, zeros.data());

  PatchexFrameDesc frame{};
  frame.header = {PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof(PatchexFrameDesc), nullptr};
  frame.frame_index = 1;
  frame.queue_family_index = e.family;
  frame.width = kWidth;
  frame.height = kHeight;
  frame.color = gpu_source.color.describe();
  frame.base_color = gpu_source.base_color.describe();
  frame.geometry = geometry(gpu_source);

  PatchexExtrapolateDesc extrapolate{};
  extrapolate.header = {PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof(PatchexExtrapolateDesc), nullptr};
  extrapolate.queue_family_index = e.family;
  extrapolate.alpha = 0.5f;
  extrapolate.width = kWidth;
  extrapolate.height = kHeight;
  extrapolate.base_color = gpu_target.base_color.describe();
  extrapolate.geometry = geometry(gpu_target);
  extrapolate.output = output.describe();

  VkCommandBuffer cmd = e.begin();
  PatchexResult submitted = patchex_submit_gbuffers(context, cmd, &frame);
  PatchexResult extrapolated = patchex_extrapolate(context, cmd, &extrapolate);
  e.submit_and_wait(cmd);
  if (submitted != PATCHEX_RESULT_SUCCESS || extrapolated != PATCHEX_RESULT_SUCCESS) {
    std::fprintf(stderr, "patchex: %s\n", patchex_last_error(context));
    return 1;
  }

  PatchexFrameStats stats{};
  stats.header = {PATCHEX_STRUCT_TYPE_FRAME_STATS, sizeof(PatchexFrameStats), nullptr};
  if (patchex_get_frame_stats(context, 1, &stats) != PATCHEX_RESULT_SUCCESS) {
    std::fprintf(stderr, "patchex_get_frame_stats: %s\n", patchex_last_error(context));
    return 1;
  }

  std::vector<uint16_t> result = read_back(e, output);
  double squared_error = 0.0, stale_error = 0.0;
  for (size_t i = 0; i < result.size(); ++i) {
    if (i % 4 == 3) continue;
    double truth = target.color[i];
    squared_error += std::pow(half_to_float(result[i]) - truth, 2.0);
    stale_error += std::pow(source.color[i] - truth, 2.0);
  }
  size_t samples = result.size() / 4 * 3;
  double psnr = 10.0 * std::log10(1.0 / (squared_error / samples));
  double stale_psnr = 10.0 * std::log10(1.0 / (stale_error / samples));
  std::printf("holes %.4f, warp %.3f ms, PSNR extrapolated %.2f dB, frame t %.2f dB\n",
              stats.extrapolations[0].hole_fraction, stats.extrapolations[0].gpu_ms[PATCHEX_STAGE_WARP], psnr,
              stale_psnr);

  patchex_destroy(context);
  destroy_image(e, output);
  destroy_frame(e, gpu_source);
  destroy_frame(e, gpu_target);
  vkDestroyCommandPool(e.device, e.pool, nullptr);
  vkDestroyDevice(e.device, nullptr);
  auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(e.instance, "vkDestroyDebugUtilsMessengerEXT"));
  destroy_messenger(e.instance, e.messenger, nullptr);
  vkDestroyInstance(e.instance, nullptr);

  bool ok = psnr > 30.0 && psnr > stale_psnr + 6.0 && g_validation_messages == 0;
  std::printf("%s (%d validation messages)\n", ok ? "ok" : "FAILED", g_validation_messages);
  return ok ? 0 : 1;
}
