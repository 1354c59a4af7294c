//! Instance, device, queue and one-shot command submission.

use std::ffi::{c_void, CStr};
use std::sync::Mutex;

use ash::vk;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

#[derive(Clone, Debug)]
pub struct EngineOptions {
    /// Khronos validation with synchronization validation. Off for timing runs.
    pub validation: bool,
    /// Picks the first physical device whose name contains this (case-insensitive); otherwise
    /// the first device, preferring a discrete or integrated GPU over a CPU driver.
    pub device_name: Option<String>,
}

impl Default for EngineOptions {
    /// Validation on, device from `PATCHEX_DEVICE` if set.
    fn default() -> Self {
        Self {
            validation: true,
            device_name: std::env::var("PATCHEX_DEVICE").ok(),
        }
    }
}

pub struct Engine {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub physical_device: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub queue_family_index: u32,
    pub device_name: String,
    command_pool: vk::CommandPool,
    /// Held around every vkQueueSubmit: threads share the one queue.
    queue_lock: Mutex<()>,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Boxed so its address, handed to the messenger, stays put.
    messages: Box<Mutex<Vec<String>>>,
    memory_properties: vk::PhysicalDeviceMemoryProperties,
}

unsafe extern "system" fn collect_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    let messages = &*(user as *const Mutex<Vec<String>>);
    let text = if data.is_null() || (*data).p_message.is_null() {
        "(no message)".to_string()
    } else {
        CStr::from_ptr((*data).p_message)
            .to_string_lossy()
            .into_owned()
    };
    if let Ok(mut messages) = messages.lock() {
        messages.push(format!("[{severity:?}] {text}"));
    }
    vk::FALSE
}

impl Engine {
    pub fn new(options: &EngineOptions) -> Result<Self, String> {
        // SAFETY: loading the system Vulkan loader; every object made below is destroyed in Drop.
        unsafe {
            let entry =
                ash::Entry::load().map_err(|e| format!("cannot load the Vulkan loader: {e}"))?;
            let app = vk::ApplicationInfo::default()
                .application_name(c"patchex harness")
                .api_version(vk::API_VERSION_1_2);
            let mut layers = Vec::new();
            let mut extensions = Vec::new();
            if options.validation {
                let available = entry
                    .enumerate_instance_layer_properties()
                    .map_err(|e| e.to_string())?;
                if !available
                    .iter()
                    .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
                {
                    return Err("VK_LAYER_KHRONOS_validation is not installed (apt-get install vulkan-validationlayers)".into());
                }
                layers.push(VALIDATION_LAYER.as_ptr());
                extensions.push(ash::ext::debug_utils::NAME.as_ptr());
                extensions.push(ash::ext::validation_features::NAME.as_ptr());
            }
            let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
            let mut features =
                vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
            let mut info = vk::InstanceCreateInfo::default()
                .application_info(&app)
                .enabled_layer_names(&layers)
                .enabled_extension_names(&extensions);
            if options.validation {
                info = info.push_next(&mut features);
            }
            let instance = entry
                .create_instance(&info, None)
                .map_err(|e| format!("vkCreateInstance: {e}"))?;

            let messages: Box<Mutex<Vec<String>>> = Box::default();
            let debug = if options.validation {
                let debug_utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
                let messenger = debug_utils
                    .create_debug_utils_messenger(
                        &vk::DebugUtilsMessengerCreateInfoEXT::default()
                            .message_severity(
                                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                                    | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                            )
                            .message_type(
                                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                            )
                            .pfn_user_callback(Some(collect_message))
                            .user_data(&*messages as *const Mutex<Vec<String>> as *mut c_void),
                        None,
                    )
                    .map_err(|e| e.to_string())?;
                Some((debug_utils, messenger))
            } else {
                None
            };

            let devices = instance
                .enumerate_physical_devices()
                .map_err(|e| e.to_string())?;
            let name_of = |pd: vk::PhysicalDevice| {
                instance
                    .get_physical_device_properties(pd)
                    .device_name_as_c_str()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            };
            let physical_device = match &options.device_name {
                Some(wanted) => devices
                    .iter()
                    .copied()
                    .find(|&pd| name_of(pd).to_lowercase().contains(&wanted.to_lowercase()))
                    .ok_or_else(|| format!("no Vulkan device named like {wanted:?}"))?,
                None => devices
                    .iter()
                    .copied()
                    .min_by_key(|&pd| {
                        match instance.get_physical_device_properties(pd).device_type {
                            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
                            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
                            _ => 2,
                        }
                    })
                    .ok_or("no Vulkan device")?,
            };
            let device_name = name_of(physical_device);
            let queue_family_index = instance
                .get_physical_device_queue_family_properties(physical_device)
                .iter()
                .position(|f| {
                    f.queue_flags
                        .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
                })
                .ok_or("no graphics+compute queue family")?
                as u32;
            let priorities = [1.0];
            let queue_info = vk::DeviceQueueCreateInfo::default()
                .queue_family_index(queue_family_index)
                .queue_priorities(&priorities);
            let device = instance
                .create_device(
                    physical_device,
                    &vk::DeviceCreateInfo::default()
                        .queue_create_infos(std::slice::from_ref(&queue_info)),
                    None,
                )
                .map_err(|e| format!("vkCreateDevice: {e}"))?;
            let queue = device.get_device_queue(queue_family_index, 0);
            let command_pool = device
                .create_command_pool(
                    &vk::CommandPoolCreateInfo::default()
                        .queue_family_index(queue_family_index)
                        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                    None,
                )
                .map_err(|e| e.to_string())?;
            let memory_properties = instance.get_physical_device_memory_properties(physical_device);
            Ok(Self {
                entry,
                instance,
                physical_device,
                device,
                queue,
                queue_family_index,
                device_name,
                command_pool,
                queue_lock: Mutex::new(()),
                debug,
                messages,
                memory_properties,
            })
        }
    }

    /// The loader's `vkGetInstanceProcAddr`, as an engine hands it to a plugin.
    pub fn get_instance_proc_addr(&self) -> vk::PFN_vkGetInstanceProcAddr {
        self.entry.static_fn().get_instance_proc_addr
    }

    /// Validation messages reported so far, taken out of the engine.
    pub fn take_validation_messages(&self) -> Vec<String> {
        std::mem::take(&mut *self.messages.lock().unwrap())
    }

    /// Panics with every validation message reported since the last call, if there is any.
    pub fn assert_validation_clean(&self) {
        let messages = self.take_validation_messages();
        assert!(
            messages.is_empty(),
            "validation reported {} message(s):\n{}",
            messages.len(),
            messages.join("\n")
        );
    }

    /// Dedicated memory for `requirements` in a memory type with `flags`.
    pub fn allocate(
        &self,
        requirements: vk::MemoryRequirements,
        flags: vk::MemoryPropertyFlags,
    ) -> vk::DeviceMemory {
        let memory_type = (0..self.memory_properties.memory_type_count)
            .find(|&i| {
                requirements.memory_type_bits & (1 << i) != 0
                    && self.memory_properties.memory_types[i as usize]
                        .property_flags
                        .contains(flags)
            })
            .expect("a memory type with the requested properties");
        let info = vk::MemoryAllocateInfo::default()
            .allocation_size(requirements.size)
            .memory_type_index(memory_type);
        // SAFETY: a plain allocation on the engine's device; its owner frees it.
        unsafe { self.device.allocate_memory(&info, None) }.expect("vkAllocateMemory")
    }

    /// Allocates a primary command buffer from the engine's own pool and begins it. The pool
    /// belongs to the thread that made the engine; other threads use [`Engine::thread_pool`].
    pub fn begin(&self) -> vk::CommandBuffer {
        self.begin_in(
            self.command_pool,
            vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT,
        )
    }

    /// Ends, submits and waits for `cmd` (from [`Engine::begin`]), then frees it.
    pub fn submit_and_wait(&self, cmd: vk::CommandBuffer) {
        self.submit_and_wait_in(self.command_pool, cmd, 1);
    }

    /// Records `record` into a fresh command buffer, submits it and waits.
    pub fn run(&self, record: impl FnOnce(vk::CommandBuffer)) {
        let cmd = self.begin();
        record(cmd);
        self.submit_and_wait(cmd);
    }

    /// Records `record` once and runs it `copies` times back to back in one submission, then
    /// waits: the GPU runs the copies with no gap between them, as under a game's steady load.
    pub fn run_repeated(&self, copies: u32, record: impl FnOnce(vk::CommandBuffer)) {
        let cmd = self.begin_in(
            self.command_pool,
            vk::CommandBufferUsageFlags::SIMULTANEOUS_USE,
        );
        record(cmd);
        self.submit_and_wait_in(self.command_pool, cmd, copies.max(1));
    }

    /// A command pool for another thread, as an engine gives each of its render threads one.
    pub fn thread_pool(&self) -> ThreadPool<'_> {
        ThreadPool {
            engine: self,
            pool: self.create_command_pool(),
        }
    }

    /// A pool of resettable command buffers on the engine's queue family; its owner destroys it.
    fn create_command_pool(&self) -> vk::CommandPool {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.queue_family_index)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a plain object on the engine's device.
        unsafe { self.device.create_command_pool(&info, None) }.expect("vkCreateCommandPool")
    }

    /// Submits `commands` (ended) to the queue in one batch, signalling `fence`, under the
    /// queue's lock: Vulkan asks that threads sharing a queue serialise their submissions.
    fn submit(&self, commands: &[vk::CommandBuffer], fence: vk::Fence) {
        let _queue = self.queue_lock.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: the commands are executable and fence unsignalled; the lock guards the queue.
        unsafe {
            self.device
                .queue_submit(
                    self.queue,
                    &[vk::SubmitInfo::default().command_buffers(commands)],
                    fence,
                )
                .expect("vkQueueSubmit");
        }
    }

    /// A primary command buffer from `pool`, which belongs to the calling thread, begun for
    /// `usage`.
    fn begin_in(
        &self,
        pool: vk::CommandPool,
        usage: vk::CommandBufferUsageFlags,
    ) -> vk::CommandBuffer {
        // SAFETY: the pool belongs to this device and to the calling thread.
        unsafe {
            let cmd = self
                .device
                .allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(pool)
                        .level(vk::CommandBufferLevel::PRIMARY)
                        .command_buffer_count(1),
                )
                .expect("vkAllocateCommandBuffers")[0];
            self.device
                .begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default().flags(usage))
                .expect("vkBeginCommandBuffer");
            cmd
        }
    }

    /// Ends `cmd`, submits it `copies` times in one batch (more than one needs SIMULTANEOUS_USE),
    /// waits, and frees it.
    fn submit_and_wait_in(&self, pool: vk::CommandPool, cmd: vk::CommandBuffer, copies: u32) {
        // SAFETY: cmd was begun from `pool`; waiting on the batch makes freeing cmd safe.
        unsafe {
            self.device
                .end_command_buffer(cmd)
                .expect("vkEndCommandBuffer");
            let fence = self
                .device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .expect("vkCreateFence");
            self.submit(&vec![cmd; copies as usize], fence);
            self.device
                .wait_for_fences(&[fence], true, u64::MAX)
                .expect("vkWaitForFences");
            self.device.destroy_fence(fence, None);
            self.device.free_command_buffers(pool, &[cmd]);
        }
    }
}

/// A render loop's frames in flight: one command buffer and fence per slot, reused, as an
/// engine records frame F while the GPU still runs frame F - 1.
pub struct FrameLoop<'a> {
    engine: &'a Engine,
    pool: vk::CommandPool,
    slots: Vec<(vk::CommandBuffer, vk::Fence)>,
}

impl<'a> FrameLoop<'a> {
    pub fn new(engine: &'a Engine, frames_in_flight: usize) -> Self {
        let pool = engine.create_command_pool();
        // SAFETY: plain objects on the engine's device, destroyed when the loop is dropped.
        unsafe {
            let device = &engine.device;
            let buffers = device
                .allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(pool)
                        .level(vk::CommandBufferLevel::PRIMARY)
                        .command_buffer_count(frames_in_flight as u32),
                )
                .expect("vkAllocateCommandBuffers");
            let slots = buffers
                .into_iter()
                .map(|cmd| {
                    let signalled =
                        vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
                    let fence = device
                        .create_fence(&signalled, None)
                        .expect("vkCreateFence");
                    (cmd, fence)
                })
                .collect();
            Self {
                engine,
                pool,
                slots,
            }
        }
    }

    /// Waits until frame `index - frames_in_flight` has finished, then records frame `index`
    /// into that slot's command buffer and submits it without waiting.
    pub fn frame(&mut self, index: u64, record: impl FnOnce(vk::CommandBuffer)) {
        let (cmd, fence) = self.slots[index as usize % self.slots.len()];
        let device = &self.engine.device;
        // SAFETY: the fence guards the slot's command buffer.
        unsafe {
            device
                .wait_for_fences(&[fence], true, u64::MAX)
                .expect("vkWaitForFences");
            device.reset_fences(&[fence]).expect("vkResetFences");
            device
                .begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .expect("vkBeginCommandBuffer");
            record(cmd);
            device.end_command_buffer(cmd).expect("vkEndCommandBuffer");
        }
        self.engine.submit(&[cmd], fence);
    }

    /// Waits until frame `index` has finished on the GPU.
    pub fn wait(&self, index: u64) {
        let (_, fence) = self.slots[index as usize % self.slots.len()];
        // SAFETY: a fence of this loop.
        unsafe {
            self.engine
                .device
                .wait_for_fences(&[fence], true, u64::MAX)
                .expect("vkWaitForFences");
        }
    }
}

impl Drop for FrameLoop<'_> {
    fn drop(&mut self) {
        let device = &self.engine.device;
        // SAFETY: waiting for every slot first; the objects are this loop's.
        unsafe {
            for &(_, fence) in &self.slots {
                let _ = device.wait_for_fences(&[fence], true, u64::MAX);
                device.destroy_fence(fence, None);
            }
            device.destroy_command_pool(self.pool, None);
        }
    }
}

/// A command pool owned by one thread; its submissions share the engine's queue.
pub struct ThreadPool<'a> {
    engine: &'a Engine,
    pool: vk::CommandPool,
}

impl ThreadPool<'_> {
    /// Records `record` into a fresh command buffer of this pool, submits it and waits.
    pub fn run(&self, record: impl FnOnce(vk::CommandBuffer)) {
        let cmd = self
            .engine
            .begin_in(self.pool, vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        record(cmd);
        self.engine.submit_and_wait_in(self.pool, cmd, 1);
    }
}

impl Drop for ThreadPool<'_> {
    fn drop(&mut self) {
        // SAFETY: every submission from the pool was waited on.
        unsafe { self.engine.device.destroy_command_pool(self.pool, None) };
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        // SAFETY: waiting idle first; every object here was made by this engine.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_device(None);
            if let Some((debug_utils, messenger)) = self.debug.take() {
                debug_utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
