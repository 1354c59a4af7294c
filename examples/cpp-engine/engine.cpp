// A small C++17 engine on raw Vulkan that uses patchex the way a game engine does: through
// <patchex.h> and the installed shared library (found with CMake's find_package), on its own
// instance, device, queue, images, command buffers and fences.
//
// patchex runs at full strength: PATCHEX_PRESET_FULL, the warp, the shadow sub-task and the
// inpainting networks. A render thread runs the frame loop with two frames in flight. Each frame
// it renders frame t of an animated scene (scene.comp: three balls rolling over a checkered floor
// under a moving camera, casting shadows, with a stencil id per ball, plus patchex's shadow
// input), renders the G-buffers of the two in-between instants t + 1/3 and t + 2/3 (colour
// included, as ground truth), records patchex_submit_gbuffers (with the shadow input chained)
// and two patchex_extrapolate calls into its own command buffer, then draws its HUD over each
// generated frame (hud.comp): patchex takes and gives pre-UI HDR colour, and the engine
// composites the UI of the instant it shows. When a frame's fence has signalled it reads
// patchex's statistics, prints the PSNR of each extrapolated frame against the instant rendered
// in full, next to the PSNR of showing frame t again, and checks the HUD of each shown frame.
//
//   patchex-cpp-engine [--frames N] [--target-shadows]      (default 30 frames)
//
// With --target-shadows the engine also gives patchex the balls' shadow mask at each
// in-between instant (PatchexTargetShadowInput; scene.comp renders it with every instant's
// G-buffers), and switches the shadows' optical flow off, which it then no longer needs.
//
// Exit status 0 when every call succeeded, the validation layer (with synchronization
// validation) reported nothing, every HUD was drawn for its own instant, and extrapolation beat
// repeating frame t on average.

#include <patchex.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "hud_spirv.h"
#include "scene_spirv.h"

namespace {

constexpr uint32_t kWidth = 160;
constexpr uint32_t kHeight = 96;
constexpr uint32_t kFramesInFlight = 2;
constexpr float kFrameTime = 1.0f / 30.0f;
constexpr std::array<float, 2> kAlphas = {1.0f / 3.0f, 2.0f / 3.0f};
constexpr int kBalls = 3;

int g_validation_messages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  std::fprintf(stderr, "validation: %s\n", data->pMessage);
  ++g_validation_messages;
  return VK_FALSE;
}

#define CHECK(call)                                                 \
  do {                                                              \
    VkResult result_ = (call);                                      \
    if (result_ != VK_SUCCESS) {                                    \
      std::fprintf(stderr, "%s failed: %d\n", #call, (int)result_); \
      std::exit(2);                                                 \
    }                                                               \
  } while (0)

// ---- Maths: column-major 4x4 matrices, as patchex and GLSL take them ----

struct Vec3 {
  float x, y, z;
  Vec3 operator-(Vec3 o) const { return {x - o.x, y - o.y, z - o.z}; }
};
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vec3 normalize(Vec3 v) {
  float length = std::sqrt(dot(v, v));
  return {v.x / length, v.y / length, v.z / length};
}

using Mat4 = std::array<float, 16>;  // m[column * 4 + row]

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 m{};
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row)
      for (int k = 0; k < 4; ++k) m[column * 4 + row] += a[k * 4 + row] * b[column * 4 + k];
  return m;
}

Mat4 look_at(Vec3 eye, Vec3 target) {
  Vec3 forward = normalize(target - eye);
  Vec3 side = normalize(cross(forward, {0.0f, 1.0f, 0.0f}));
  Vec3 up = cross(side, forward);
  return {side.x, up.x, -forward.x, 0.0f, side.y, up.y, -forward.y, 0.0f,
          side.z, up.z, -forward.z, 0.0f, -dot(side, eye), -dot(up, eye), dot(forward, eye), 1.0f};
}

constexpr float kNear = 0.1f, kFar = 100.0f;

// Vulkan clip space: y down the image, depth 0 at the near plane and 1 at the far plane.
Mat4 perspective() {
  float f = 1.0f / std::tan(0.5f * 50.0f * 3.14159265f / 180.0f);
  float aspect = float(kWidth) / float(kHeight);
  Mat4 m{};
  m[0] = f / aspect;
  m[5] = -f;
  m[10] = kFar / (kNear - kFar);
  m[11] = -1.0f;
  m[14] = kNear * kFar / (kNear - kFar);
  return m;
}

// ---- The scene: where everything is at a time ----

Vec3 eye_at(float t) { return {-1.0f + 0.8f * t, 2.2f, 6.0f}; }
Mat4 view_at(float t) { return look_at(eye_at(t), {0.3f * t, 0.5f, 0.0f}); }

std::array<float, 4> ball_at(int i, float t) {
  const float radius[kBalls] = {0.5f, 0.4f, 0.35f};
  switch (i) {
    case 0: return {-2.0f + 2.4f * t, radius[0], 0.5f, radius[0]};
    case 1: return {1.5f * std::cos(1.3f * t), radius[1], -0.5f + 1.5f * std::sin(1.3f * t), radius[1]};
    default: return {0.8f, radius[2], 1.8f - 1.8f * t, radius[2]};
  }
}

// The `Instant` uniform block of scene.comp (std140).
struct Instant {
  Mat4 view_projection;
  Mat4 earlier_view_projection;
  std::array<float, 4> eye;
  std::array<float, 4> sun;
  std::array<float, 4> balls[kBalls];
  std::array<float, 4> earlier_balls[kBalls];
};

Instant instant_at(float t, float earlier) {
  Instant instant{};
  instant.view_projection = multiply(perspective(), view_at(t));
  instant.earlier_view_projection = multiply(perspective(), view_at(earlier));
  Vec3 eye = eye_at(t);
  instant.eye = {eye.x, eye.y, eye.z, 1.0f};
  Vec3 sun = normalize({0.4f, 0.8f, 0.3f});
  instant.sun = {sun.x, sun.y, sun.z, 0.0f};
  for (int i = 0; i < kBalls; ++i) {
    instant.balls[i] = ball_at(i, t);
    instant.earlier_balls[i] = ball_at(i, earlier);
  }
  return instant;
}

PatchexCamera camera_at(float t) {
  PatchexCamera camera{};
  Mat4 view = view_at(t), projection = perspective();
  std::memcpy(camera.view, view.data(), sizeof camera.view);
  std::memcpy(camera.projection, projection.data(), sizeof camera.projection);
  camera.near_plane = kNear;
  camera.far_plane = kFar;
  camera.depth_convention = PATCHEX_DEPTH_HARDWARE;
  return camera;
}

// The HUD bar's length at time t: one sweep of the image width every two seconds.
uint32_t hud_bar_length(float t) {
  float loop = t * 0.5f - std::floor(t * 0.5f);
  return uint32_t(loop * float(kWidth));
}

// ---- Vulkan objects ----

struct Engine {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;

  uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const {
    VkPhysicalDeviceMemoryProperties properties;
    vkGetPhysicalDeviceMemoryProperties(physical_device, &properties);
    for (uint32_t i = 0; i < properties.memoryTypeCount; ++i)
      if ((bits & (1u << i)) && (properties.memoryTypes[i].propertyFlags & flags) == flags) return i;
    std::fprintf(stderr, "no suitable memory type\n");
    std::exit(2);
  }

  VkDeviceMemory allocate(VkMemoryRequirements requirements, VkMemoryPropertyFlags flags) const {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = requirements.size;
    info.memoryTypeIndex = memory_type(requirements.memoryTypeBits, flags);
    VkDeviceMemory memory;
    CHECK(vkAllocateMemory(device, &info, nullptr, &memory));
    return memory;
  }
};

Engine create_engine() {
  Engine e;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "patchex C++ engine example";
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
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
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
  VkFormatProperties stencil;
  vkGetPhysicalDeviceFormatProperties(e.physical_device, VK_FORMAT_R8_UINT, &stencil);
  if (!(stencil.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT)) {
    std::fprintf(stderr, "the device cannot write R8_UINT storage images (the stencil id)\n");
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
  return e;
}

// An engine image, kept in GENERAL: written by the renderer, read (and written) by patchex.
struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkImageUsageFlags usage = 0;

  PatchexImage describe() const {
    return PatchexImage{image, view, format, kWidth, kHeight, VK_IMAGE_LAYOUT_GENERAL, usage};
  }
};

Image create_image(const Engine& e, VkFormat format) {
  Image image;
  image.format = format;
  image.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
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
  image.memory = e.allocate(requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  CHECK(vkBindImageMemory(e.device, image.image, image.memory, 0));
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = image.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  CHECK(vkCreateImageView(e.device, &view, nullptr, &image.view));
  return image;
}

void destroy_image(const Engine& e, Image& image) {
  vkDestroyImageView(e.device, image.view, nullptr);
  vkDestroyImage(e.device, image.image, nullptr);
  vkFreeMemory(e.device, image.memory, nullptr);
}

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
};

Buffer create_buffer(const Engine& e, VkDeviceSize size, VkBufferUsageFlags usage) {
  Buffer b;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  CHECK(vkCreateBuffer(e.device, &info, nullptr, &b.buffer));
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(e.device, b.buffer, &requirements);
  b.memory = e.allocate(requirements, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  CHECK(vkBindBufferMemory(e.device, b.buffer, b.memory, 0));
  CHECK(vkMapMemory(e.device, b.memory, 0, size, 0, &b.mapped));
  return b;
}

void destroy_buffer(const Engine& e, Buffer& b) {
  vkDestroyBuffer(e.device, b.buffer, nullptr);
  vkFreeMemory(e.device, b.memory, nullptr);
}

// The G-buffers of one instant and its shadow input, in the formats scene.comp writes.
struct GBuffer {
  Image color, base_color, normal, depth, stencil, motion, shadow_mask, color_without_dynamic_shadows;

  std::array<Image*, 8> images() {
    return {&color, &base_color, &normal, &depth, &stencil, &motion, &shadow_mask, &color_without_dynamic_shadows};
  }
};

GBuffer create_gbuffer(const Engine& e) {
  return GBuffer{create_image(e, VK_FORMAT_R16G16B16A16_SFLOAT), create_image(e, VK_FORMAT_R8G8B8A8_UNORM),
                 create_image(e, VK_FORMAT_R16G16B16A16_SFLOAT), create_image(e, VK_FORMAT_R32_SFLOAT),
                 create_image(e, VK_FORMAT_R8_UINT),             create_image(e, VK_FORMAT_R32G32_SFLOAT),
                 create_image(e, VK_FORMAT_R32_SFLOAT),          create_image(e, VK_FORMAT_R16G16B16A16_SFLOAT)};
}

PatchexShadowInput shadow_input(const GBuffer& g) {
  PatchexShadowInput input{};
  input.header = {PATCHEX_STRUCT_TYPE_SHADOW_INPUT, sizeof(PatchexShadowInput), nullptr};
  input.mask = g.shadow_mask.describe();
  input.color_without_dynamic_shadows = g.color_without_dynamic_shadows.describe();
  return input;
}

PatchexGeometry geometry(const GBuffer& g, float time) {
  PatchexGeometry geometry{};
  geometry.depth = g.depth.describe();
  geometry.normal = g.normal.describe();
  geometry.normal_encoding = PATCHEX_NORMAL_SIGNED;
  geometry.stencil = g.stencil.describe();
  geometry.motion_vectors = g.motion.describe();
  geometry.motion_vector_scale[0] = geometry.motion_vector_scale[1] = 1.0f;
  geometry.camera = camera_at(time);
  return geometry;
}

// A compute pipeline over `storage_images` storage images (bindings 0, 1, ...), then optionally
// a uniform buffer, with `push_bytes` of push constants.
struct ComputePass {
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
};

template <size_t N>
ComputePass create_pass(const Engine& e, const uint32_t (&spirv)[N], uint32_t storage_images, bool uniform,
                        uint32_t push_bytes) {
  ComputePass r;
  std::vector<VkDescriptorSetLayoutBinding> bindings(storage_images + (uniform ? 1 : 0));
  for (uint32_t i = 0; i < bindings.size(); ++i) {
    bindings[i].binding = i;
    bindings[i].descriptorType = i < storage_images ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.bindingCount = bindings.size();
  set_info.pBindings = bindings.data();
  CHECK(vkCreateDescriptorSetLayout(e.device, &set_info, nullptr, &r.set_layout));
  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &r.set_layout;
  layout_info.pushConstantRangeCount = push_bytes ? 1 : 0;
  layout_info.pPushConstantRanges = &push;
  CHECK(vkCreatePipelineLayout(e.device, &layout_info, nullptr, &r.layout));
  VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  module_info.codeSize = sizeof spirv;
  module_info.pCode = spirv;
  VkShaderModule module;
  CHECK(vkCreateShaderModule(e.device, &module_info, nullptr, &module));
  VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipeline_info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline_info.stage.module = module;
  pipeline_info.stage.pName = "main";
  pipeline_info.layout = r.layout;
  CHECK(vkCreateComputePipelines(e.device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &r.pipeline));
  vkDestroyShaderModule(e.device, module, nullptr);
  return r;
}

void destroy_pass(const Engine& e, ComputePass& r) {
  vkDestroyPipeline(e.device, r.pipeline, nullptr);
  vkDestroyPipelineLayout(e.device, r.layout, nullptr);
  vkDestroyDescriptorSetLayout(e.device, r.set_layout, nullptr);
}

constexpr uint32_t kImageBindings = 8;
constexpr uint32_t kInstantsPerFrame = 1 + kAlphas.size();

// The renderer (scene.comp), one descriptor set per instant it renders, and the UI pass
// (hud.comp), one set per generated frame.
struct Passes {
  ComputePass renderer, hud;
  VkDescriptorPool pool = VK_NULL_HANDLE;
};

Passes create_passes(const Engine& e) {
  Passes r;
  r.renderer = create_pass(e, scene_spirv, kImageBindings, true, 0);
  r.hud = create_pass(e, hud_spirv, 2, false, sizeof(uint32_t));
  const uint32_t scene_sets = kFramesInFlight * kInstantsPerFrame, hud_sets = kFramesInFlight * kAlphas.size();
  VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, scene_sets * kImageBindings + hud_sets * 2},
                                  {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, scene_sets}};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = scene_sets + hud_sets;
  pool_info.poolSizeCount = 2;
  pool_info.pPoolSizes = sizes;
  CHECK(vkCreateDescriptorPool(e.device, &pool_info, nullptr, &r.pool));
  return r;
}

void destroy_passes(const Engine& e, Passes& r) {
  vkDestroyDescriptorPool(e.device, r.pool, nullptr);
  destroy_pass(e, r.renderer);
  destroy_pass(e, r.hud);
}

void write_storage_image(VkDescriptorSet set, uint32_t binding, const VkDescriptorImageInfo* image,
                         VkWriteDescriptorSet& write) {
  write = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  write.pImageInfo = image;
}

// Everything one frame in flight owns. Instant 0 is frame t; instant 1 + k the target alpha k.
struct Slot {
  std::array<GBuffer, kInstantsPerFrame> gbuffers;
  std::array<Image, kAlphas.size()> outputs;   // patchex's pre-UI frames
  std::array<Image, kAlphas.size()> displays;  // what the engine shows: tone-mapped, with its HUD
  std::array<VkDescriptorSet, kInstantsPerFrame> sets{};
  std::array<VkDescriptorSet, kAlphas.size()> hud_sets{};
  std::array<uint32_t, kAlphas.size()> hud_bars{};
  Buffer uniforms;  // one Instant per instant
  // Frame t's colour, then per target its rendered colour and patchex's output, then the
  // displayed frames.
  Buffer readback;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  uint64_t frame_index = 0;  // 0: nothing recorded yet
};

constexpr VkDeviceSize kImageBytes = VkDeviceSize(kWidth) * kHeight * 8;    // RGBA16F
constexpr VkDeviceSize kDisplayBytes = VkDeviceSize(kWidth) * kHeight * 4;  // RGBA8
constexpr uint32_t kReadbackImages = 1 + 2 * kAlphas.size();

Slot create_slot(const Engine& e, const Passes& r, VkCommandPool pool) {
  Slot s;
  for (GBuffer& g : s.gbuffers) g = create_gbuffer(e);
  for (Image& output : s.outputs) output = create_image(e, VK_FORMAT_R16G16B16A16_SFLOAT);
  for (Image& display : s.displays) display = create_image(e, VK_FORMAT_R8G8B8A8_UNORM);
  s.uniforms = create_buffer(e, sizeof(Instant) * kInstantsPerFrame, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  s.readback = create_buffer(e, kImageBytes * kReadbackImages + kDisplayBytes * kAlphas.size(),
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT);
  std::array<VkDescriptorSetLayout, kInstantsPerFrame> layouts;
  layouts.fill(r.renderer.set_layout);
  VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocate.descriptorPool = r.pool;
  allocate.descriptorSetCount = kInstantsPerFrame;
  allocate.pSetLayouts = layouts.data();
  CHECK(vkAllocateDescriptorSets(e.device, &allocate, s.sets.data()));
  std::array<VkDescriptorSetLayout, kAlphas.size()> hud_layouts;
  hud_layouts.fill(r.hud.set_layout);
  allocate.descriptorSetCount = kAlphas.size();
  allocate.pSetLayouts = hud_layouts.data();
  CHECK(vkAllocateDescriptorSets(e.device, &allocate, s.hud_sets.data()));
  for (uint32_t k = 0; k < kAlphas.size(); ++k) {
    VkDescriptorImageInfo images[2] = {{VK_NULL_HANDLE, s.outputs[k].view, VK_IMAGE_LAYOUT_GENERAL},
                                       {VK_NULL_HANDLE, s.displays[k].view, VK_IMAGE_LAYOUT_GENERAL}};
    VkWriteDescriptorSet writes[2];
    for (uint32_t i = 0; i < 2; ++i) write_storage_image(s.hud_sets[k], i, &images[i], writes[i]);
    vkUpdateDescriptorSets(e.device, 2, writes, 0, nullptr);
  }
  for (uint32_t instant = 0; instant < kInstantsPerFrame; ++instant) {
    std::array<VkDescriptorImageInfo, kImageBindings> images;
    std::array<VkWriteDescriptorSet, kImageBindings + 1> writes{};
    auto gbuffer_images = s.gbuffers[instant].images();
    for (uint32_t i = 0; i < kImageBindings; ++i) {
      images[i] = {VK_NULL_HANDLE, gbuffer_images[i]->view, VK_IMAGE_LAYOUT_GENERAL};
      write_storage_image(s.sets[instant], i, &images[i], writes[i]);
    }
    VkDescriptorBufferInfo uniform{s.uniforms.buffer, sizeof(Instant) * instant, sizeof(Instant)};
    writes[kImageBindings] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[kImageBindings].dstSet = s.sets[instant];
    writes[kImageBindings].dstBinding = kImageBindings;
    writes[kImageBindings].descriptorCount = 1;
    writes[kImageBindings].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    writes[kImageBindings].pBufferInfo = &uniform;
    vkUpdateDescriptorSets(e.device, writes.size(), writes.data(), 0, nullptr);
  }
  VkCommandBufferAllocateInfo cmd_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cmd_info.commandPool = pool;
  cmd_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cmd_info.commandBufferCount = 1;
  CHECK(vkAllocateCommandBuffers(e.device, &cmd_info, &s.cmd));
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence_info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  CHECK(vkCreateFence(e.device, &fence_info, nullptr, &s.fence));
  return s;
}

void destroy_slot(const Engine& e, Slot& s) {
  for (GBuffer& g : s.gbuffers)
    for (Image* image : g.images()) destroy_image(e, *image);
  for (Image& output : s.outputs) destroy_image(e, output);
  for (Image& display : s.displays) destroy_image(e, display);
  destroy_buffer(e, s.uniforms);
  destroy_buffer(e, s.readback);
  vkDestroyFence(e.device, s.fence, nullptr);
}

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags from, VkAccessFlags written, VkPipelineStageFlags to,
             VkAccessFlags read) {
  VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  memory.srcAccessMask = written;
  memory.dstAccessMask = read;
  vkCmdPipelineBarrier(cmd, from, to, 0, 1, &memory, 0, nullptr, 0, nullptr);
}

// Moves new images from UNDEFINED to GENERAL, where they stay.
void initialize_layouts(VkCommandBuffer cmd, Slot& s) {
  std::vector<VkImageMemoryBarrier> barriers;
  auto add = [&](const Image& image) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image.image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    barriers.push_back(b);
  };
  for (GBuffer& g : s.gbuffers)
    for (Image* image : g.images()) add(*image);
  for (Image& output : s.outputs) add(output);
  for (Image& display : s.displays) add(display);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0,
                       nullptr, barriers.size(), barriers.data());
}

void copy_to_readback(VkCommandBuffer cmd, const Image& image, const Buffer& readback, VkDeviceSize offset) {
  VkBufferImageCopy copy{};
  copy.bufferOffset = offset;
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {kWidth, kHeight, 1};
  vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_GENERAL, readback.buffer, 1, &copy);
}

float half_to_float(uint16_t h) {
  uint32_t sign = (h >> 15) & 1, exponent = (h >> 10) & 31, mantissa = h & 1023;
  float value = exponent == 0 ? std::ldexp(float(mantissa), -24) : std::ldexp(float(mantissa | 1024), int(exponent) - 25);
  return sign ? -value : value;
}

// PSNR of two RGBA16F images over RGB, peak 1 (the scene's colours stay under 1).
double psnr(const uint16_t* a, const uint16_t* b) {
  double squared = 0.0;
  size_t samples = 0;
  for (size_t i = 0; i < size_t(kWidth) * kHeight * 4; ++i) {
    if (i % 4 == 3) continue;
    double d = double(half_to_float(a[i])) - double(half_to_float(b[i]));
    squared += d * d;
    ++samples;
  }
  return squared == 0.0 ? 99.0 : 10.0 * std::log10(double(samples) / squared);
}

// Whether the displayed RGBA8 frame shows exactly the HUD bar of `bar_length` pixels: white
// inside it, the scene right after it (rows 2 to 5, as hud.comp draws them).
bool hud_drawn(const uint8_t* display, uint32_t bar_length) {
  for (uint32_t y = 2; y < 6; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const uint8_t* texel = display + (size_t(y) * kWidth + x) * 4;
      bool white = texel[0] == 255 && texel[1] == 255 && texel[2] == 255;
      // The tone-mapped scene never reaches 255 (c / (1 + c) with c under 1).
      if (white != (x < bar_length)) return false;
    }
  return true;
}

struct Totals {
  int frames = 0;
  int failures = 0;
  int huds_checked = 0;
  double extrapolated_psnr = 0.0, repeated_psnr = 0.0;
  int measured = 0;
};

// Reports a finished frame: its statistics and the PSNR of each extrapolation.
void report(const Slot& s, PatchexContext* context, Totals& totals) {
  PatchexFrameStats stats{};
  stats.header = {PATCHEX_STRUCT_TYPE_FRAME_STATS, sizeof(PatchexFrameStats), nullptr};
  if (patchex_get_frame_stats(context, s.frame_index, &stats) != PATCHEX_RESULT_SUCCESS) {
    std::fprintf(stderr, "frame %llu: patchex_get_frame_stats: %s\n", (unsigned long long)s.frame_index,
                 patchex_last_error(context));
    ++totals.failures;
    return;
  }
  auto image = [&](uint32_t index) {
    return static_cast<const uint16_t*>(s.readback.mapped) + kImageBytes / 2 * index;
  };
  for (uint32_t k = 0; k < kAlphas.size(); ++k) {
    const uint16_t* truth = image(1 + 2 * k);
    double extrapolated = psnr(image(2 + 2 * k), truth), repeated = psnr(image(0), truth);
    const PatchexExtrapolationStats& x = stats.extrapolations[k];
    float gpu_ms = 0.0f;
    for (float stage_ms : x.gpu_ms) gpu_ms += stage_ms;
    std::printf(
        "frame %3llu  t + %.2f: PSNR %6.2f dB (frame t repeated: %6.2f dB)  holes %5.2f%%  repaired %5.2f%%  "
        "patchex %.2f ms%s\n",
        (unsigned long long)s.frame_index, kAlphas[k], extrapolated, repeated, 100.0 * x.hole_fraction,
        100.0 * x.repaired_fraction, gpu_ms, x.render_instead_reasons ? "  (render instead)" : "");
    totals.extrapolated_psnr += extrapolated;
    totals.repeated_psnr += repeated;
    ++totals.measured;
    if (!hud_drawn(static_cast<const uint8_t*>(s.readback.mapped) + kImageBytes * kReadbackImages + kDisplayBytes * k,
                   s.hud_bars[k])) {
      std::fprintf(stderr, "frame %llu t + %.2f: the HUD is not the target instant's\n",
                   (unsigned long long)s.frame_index, kAlphas[k]);
      ++totals.failures;
    }
    ++totals.huds_checked;
  }
}

// The render thread: the whole frame loop, as an engine's render thread runs it.
void render_thread(const Engine& e, PatchexContext* context, int frames, bool target_shadows, Totals& totals) {
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = e.family;
  VkCommandPool pool;
  CHECK(vkCreateCommandPool(e.device, &pool_info, nullptr, &pool));
  Passes passes = create_passes(e);
  std::array<Slot, kFramesInFlight> slots;
  for (Slot& s : slots) s = create_slot(e, passes, pool);
  bool first_use[kFramesInFlight] = {true, true};

  for (uint64_t frame = 1; frame <= uint64_t(frames); ++frame) {
    Slot& s = slots[frame % kFramesInFlight];
    // The slot's previous frame (frame - kFramesInFlight) must be done before its reuse.
    CHECK(vkWaitForFences(e.device, 1, &s.fence, VK_TRUE, UINT64_MAX));
    if (s.frame_index != 0) report(s, context, totals);
    CHECK(vkResetFences(e.device, 1, &s.fence));

    const float t = float(frame) * kFrameTime;
    Instant* instants = static_cast<Instant*>(s.uniforms.mapped);
    instants[0] = instant_at(t, t - kFrameTime);
    for (uint32_t k = 0; k < kAlphas.size(); ++k) instants[1 + k] = instant_at(t + kAlphas[k] * kFrameTime, t);

    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    CHECK(vkBeginCommandBuffer(s.cmd, &begin));
    if (first_use[frame % kFramesInFlight]) initialize_layouts(s.cmd, s);
    first_use[frame % kFramesInFlight] = false;
    // The copies of the frame that last used this slot were read on the host; now overwrite.
    barrier(s.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0);
    vkCmdBindPipeline(s.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.renderer.pipeline);
    for (uint32_t instant = 0; instant < kInstantsPerFrame; ++instant) {
      vkCmdBindDescriptorSets(s.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.renderer.layout, 0, 1, &s.sets[instant],
                              0, nullptr);
      vkCmdDispatch(s.cmd, (kWidth + 7) / 8, (kHeight + 7) / 8, 1);
    }

    // patchex: frame t, then its two in-between instants. Its barriers order it after the
    // renderer's writes; no barrier of ours is needed around the calls.
    const GBuffer& source = s.gbuffers[0];
    PatchexShadowInput shadows = shadow_input(source);
    PatchexFrameDesc desc{};
    desc.header = {PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof(PatchexFrameDesc), &shadows};
    desc.frame_index = frame;
    desc.queue_family_index = e.family;
    desc.width = kWidth;
    desc.height = kHeight;
    desc.color = source.color.describe();
    desc.base_color = source.base_color.describe();
    desc.geometry = geometry(source, t);
    PatchexResult result = patchex_submit_gbuffers(context, s.cmd, &desc);
    if (result != PATCHEX_RESULT_SUCCESS) {
      std::fprintf(stderr, "frame %llu: patchex_submit_gbuffers: %s\n", (unsigned long long)frame,
                   patchex_last_error(context));
      ++totals.failures;
    }
    for (uint32_t k = 0; k < kAlphas.size(); ++k) {
      const GBuffer& target = s.gbuffers[1 + k];
      // The balls' shadows where they are at this instant, rendered with its G-buffers.
      PatchexTargetShadowInput target_mask{};
      target_mask.header = {PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT, sizeof(PatchexTargetShadowInput), nullptr};
      target_mask.mask = target.shadow_mask.describe();
      PatchexExtrapolateDesc extrapolate{};
      extrapolate.header = {PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof(PatchexExtrapolateDesc),
                            target_shadows ? &target_mask : nullptr};
      extrapolate.queue_family_index = e.family;
      extrapolate.alpha = kAlphas[k];
      extrapolate.width = kWidth;
      extrapolate.height = kHeight;
      extrapolate.base_color = target.base_color.describe();
      extrapolate.geometry = geometry(target, t + kAlphas[k] * kFrameTime);
      extrapolate.output = s.outputs[k].describe();
      result = patchex_extrapolate(context, s.cmd, &extrapolate);
      if (result < 0) {
        std::fprintf(stderr, "frame %llu: patchex_extrapolate: %s\n", (unsigned long long)frame,
                     patchex_last_error(context));
        ++totals.failures;
      }
    }

    // The UI, drawn over each generated frame for its own instant. patchex's barriers made its
    // output visible to whatever comes next, and the pipeline and descriptor sets it bound are
    // ours to rebind.
    vkCmdBindPipeline(s.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.hud.pipeline);
    for (uint32_t k = 0; k < kAlphas.size(); ++k) {
      s.hud_bars[k] = hud_bar_length(t + kAlphas[k] * kFrameTime);
      vkCmdBindDescriptorSets(s.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.hud.layout, 0, 1, &s.hud_sets[k], 0,
                              nullptr);
      vkCmdPushConstants(s.cmd, passes.hud.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(uint32_t), &s.hud_bars[k]);
      vkCmdDispatch(s.cmd, (kWidth + 7) / 8, (kHeight + 7) / 8, 1);
    }

    // Out to the host: frame t's colour, per target the rendered colour and the output, and
    // the displayed frames.
    barrier(s.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_ACCESS_TRANSFER_READ_BIT);
    copy_to_readback(s.cmd, source.color, s.readback, 0);
    for (uint32_t k = 0; k < kAlphas.size(); ++k) {
      copy_to_readback(s.cmd, s.gbuffers[1 + k].color, s.readback, kImageBytes * (1 + 2 * k));
      copy_to_readback(s.cmd, s.outputs[k], s.readback, kImageBytes * (2 + 2 * k));
      copy_to_readback(s.cmd, s.displays[k], s.readback, kImageBytes * kReadbackImages + kDisplayBytes * k);
    }
    barrier(s.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
            VK_ACCESS_HOST_READ_BIT);
    CHECK(vkEndCommandBuffer(s.cmd));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &s.cmd;
    CHECK(vkQueueSubmit(e.queue, 1, &submit, s.fence));
    s.frame_index = frame;
    ++totals.frames;
  }

  // The last frames in flight.
  for (uint64_t frame = uint64_t(frames) + 1; frame <= uint64_t(frames) + kFramesInFlight; ++frame) {
    Slot& s = slots[frame % kFramesInFlight];
    CHECK(vkWaitForFences(e.device, 1, &s.fence, VK_TRUE, UINT64_MAX));
    if (s.frame_index != 0) report(s, context, totals);
  }
  for (Slot& s : slots) destroy_slot(e, s);
  destroy_passes(e, passes);
  vkDestroyCommandPool(e.device, pool, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 30;
  bool target_shadows = false;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--frames" && i + 1 < argc) frames = std::atoi(argv[++i]);
    else if (std::string(argv[i]) == "--target-shadows") target_shadows = true;
    else frames = 0;
  }
  if (frames < 1) {
    std::fprintf(stderr, "usage: %s [--frames N] [--target-shadows]   (N >= 1)\n", argv[0]);
    return 2;
  }
  std::printf("patchex ABI version %u, preset FULL with the shadow input%s, %dx%d, %d frames, two extrapolations each\n",
              patchex_abi_version(), target_shadows ? " and the target's shadow mask" : "",
              kWidth, kHeight, frames);
  Engine e = create_engine();

  // Created at load time on the main thread; used only by the render thread afterwards.
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
  info.frames_in_flight = kFramesInFlight;
  info.preset = PATCHEX_PRESET_FULL;
  // With the target's shadow mask on every extrapolation, the shadows need no optical flow.
  PatchexShadowFlowSettings no_flow{};
  no_flow.header = {PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS, sizeof(PatchexShadowFlowSettings), nullptr};
  no_flow.levels = 0;
  no_flow.iterations = PATCHEX_DEFAULT_FLOW_ITERATIONS;
  no_flow.window_radius = PATCHEX_DEFAULT_FLOW_WINDOW_RADIUS;
  no_flow.poly_radius = PATCHEX_DEFAULT_FLOW_POLY_RADIUS;
  no_flow.poly_sigma = PATCHEX_DEFAULT_FLOW_POLY_SIGMA;
  if (target_shadows) info.header.next = &no_flow;
  PatchexContext* context = nullptr;
  if (patchex_create(&info, &context) != PATCHEX_RESULT_SUCCESS) {
    std::fprintf(stderr, "patchex_create: %s\n", patchex_last_error(nullptr));
    return 1;
  }

  Totals totals;
  std::thread render(render_thread, std::cref(e), context, frames, target_shadows, std::ref(totals));
  render.join();

  patchex_destroy(context);
  vkDestroyDevice(e.device, nullptr);
  auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(e.instance, "vkDestroyDebugUtilsMessengerEXT"));
  destroy_messenger(e.instance, e.messenger, nullptr);
  vkDestroyInstance(e.instance, nullptr);

  double extrapolated = totals.extrapolated_psnr / std::max(totals.measured, 1);
  double repeated = totals.repeated_psnr / std::max(totals.measured, 1);
  std::printf("mean PSNR over %d extrapolated frames: %.2f dB (frame t repeated: %.2f dB)\n", totals.measured,
              extrapolated, repeated);
  std::printf("HUD drawn for its own instant over %d generated frames\n", totals.huds_checked);
  bool ok = totals.failures == 0 && totals.measured == 2 * frames && totals.huds_checked == 2 * frames &&
            extrapolated > repeated + 3.0 && g_validation_messages == 0;
  std::printf("%s (%d validation messages)\n", ok ? "ok" : "FAILED", g_validation_messages);
  return ok ? 0 : 1;
}
