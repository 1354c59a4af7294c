/*
 * A minimal C engine for the C tests: a Vulkan device on the first physical device with the
 * validation layers and synchronization validation on (every message counted), one command
 * buffer submitted and waited for, engine images in the layouts an engine keeps them, and
 * patchex calls checked against the result they must return. Written against the installed
 * <patchex.h> alone, in C11. Each test program includes it once.
 */
#ifndef PATCHEX_TEST_ENGINE_H
#define PATCHEX_TEST_ENGINE_H

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
  app.pApplicationName = "patchex C11 test";
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

static void destroy_gpu(void) {
  vkDestroyFence(gpu.device, gpu.fence, NULL);
  vkDestroyCommandPool(gpu.device, gpu.pool, NULL);
  vkDestroyDevice(gpu.device, NULL);
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
      (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
          gpu.instance, "vkDestroyDebugUtilsMessengerEXT");
  destroy_messenger(gpu.instance, gpu.messenger, NULL);
  vkDestroyInstance(gpu.instance, NULL);
}

/* Prints the verdict the Rust side looks for, and the exit code that goes with it. */
static int verdict(void) {
  printf("%s (%d failures, %d validation messages)\n",
         failures == 0 && validation_messages == 0 ? "ok" : "FAILED", failures,
         validation_messages);
  return failures == 0 && validation_messages == 0 ? 0 : 1;
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
  uint32_t width, height;
} Image;

static uint32_t width, height;

/* An image of `w` x `h` texels. */
static Image create_image_sized(VkFormat format, uint32_t texel_bytes, VkImageUsageFlags usage,
                                uint32_t w, uint32_t h) {
  Image image = {0};
  image.format = format;
  image.texel_bytes = texel_bytes;
  image.width = w;
  image.height = h;
  image.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  image.layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImageCreateInfo info = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent.width = w;
  info.extent.height = h;
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

/* An image of the frame's extent. */
static Image create_image(VkFormat format, uint32_t texel_bytes, VkImageUsageFlags usage) {
  return create_image_sized(format, texel_bytes, usage, width, height);
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

static VkBufferImageCopy whole_image(const Image *image) {
  VkBufferImageCopy copy;
  memset(&copy, 0, sizeof copy);
  copy.imageSubresource.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
  copy.imageSubresource.layerCount = 1;
  copy.imageExtent.width = image->width;
  copy.imageExtent.height = image->height;
  copy.imageExtent.depth = 1;
  return copy;
}

/* An input image of `w` x `h` texels filled from `bytes` and left in
   SHADER_READ_ONLY_OPTIMAL. */
static Image input_image_sized(VkFormat format, uint32_t texel_bytes, uint32_t w, uint32_t h,
                               const unsigned char *bytes) {
  Image image = create_image_sized(format, texel_bytes, VK_IMAGE_USAGE_SAMPLED_BIT, w, h);
  size_t size = (size_t)w * h * texel_bytes;
  Buffer staging = create_buffer(size);
  memcpy(staging.mapped, bytes, size);
  begin();
  transition(&image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  VkBufferImageCopy copy = whole_image(&image);
  vkCmdCopyBufferToImage(gpu.cmd, staging.buffer, image.image,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  transition(&image, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  submit_and_wait();
  destroy_buffer(&staging);
  return image;
}

/* An input image of the frame's extent. */
static Image input_image(VkFormat format, uint32_t texel_bytes, const unsigned char *bytes) {
  return input_image_sized(format, texel_bytes, width, height, bytes);
}

/* An image patchex writes, kept in GENERAL. */
static Image output_image(VkFormat format, uint32_t texel_bytes, VkImageUsageFlags usage) {
  Image image = create_image(format, texel_bytes, usage);
  begin();
  transition(&image, VK_IMAGE_LAYOUT_GENERAL);
  submit_and_wait();
  return image;
}

/* Copies `image` into `bytes` (its width * height * texel_bytes), keeping its layout. */
static void read_image(Image *image, void *bytes) {
  size_t size = (size_t)image->width * image->height * image->texel_bytes;
  Buffer staging = create_buffer(size);
  begin();
  VkImageLayout kept = image->layout;
  transition(image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  VkBufferImageCopy copy = whole_image(image);
  vkCmdCopyImageToBuffer(gpu.cmd, image->image, image->layout, staging.buffer, 1, &copy);
  transition(image, kept);
  VkMemoryBarrier to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(gpu.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &to_host, 0, NULL, 0, NULL);
  submit_and_wait();
  memcpy(bytes, staging.mapped, size);
  destroy_buffer(&staging);
}

static PatchexImage describe(const Image *image) {
  PatchexImage d;
  d.image = image->image;
  d.view = image->view;
  d.format = image->format;
  d.width = image->width;
  d.height = image->height;
  d.layout = image->layout;
  d.usage = image->usage;
  return d;
}

static PatchexStructHeader header(PatchexStructType type, uint32_t size, const void *next) {
  PatchexStructHeader h;
  h.struct_type = type;
  h.struct_size = size;
  h.next = next;
  return h;
}

/* A create info on this engine's device for frames up to width x height, with `chain`. */
static PatchexCreateInfo create_info(PatchexPreset preset, uint32_t frames_in_flight,
                                     const void *chain) {
  PatchexCreateInfo info;
  memset(&info, 0, sizeof info);
  info.header = header(PATCHEX_STRUCT_TYPE_CREATE_INFO, sizeof info, chain);
  info.instance = gpu.instance;
  info.physical_device = gpu.physical_device;
  info.device = gpu.device;
  info.get_instance_proc_addr = vkGetInstanceProcAddr;
  info.get_device_proc_addr = vkGetDeviceProcAddr;
  info.queue_family_index = gpu.family;
  info.max_width = width;
  info.max_height = height;
  info.frames_in_flight = frames_in_flight;
  info.preset = preset;
  info.log_callback = on_log;
  return info;
}

#endif
