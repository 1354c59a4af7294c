//! The renderer's own Vulkan instance and device. The renderer is an application, not the
//! plugin, so it owns everything it creates.

use super::validation::{messenger_info, MessageLog};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::ffi::{c_char, CStr};
use std::sync::{Arc, Mutex};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

#[derive(Clone, Copy, Debug, Default)]
pub struct GpuOptions {
    /// Enable the Khronos validation layer with synchronization validation; messages are
    /// collected and returned by [`Gpu::take_validation_messages`].
    pub validation: bool,
}

pub struct Gpu {
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) command_pool: vk::CommandPool,
    pub(crate) memory_properties: vk::PhysicalDeviceMemoryProperties,
    /// Nanoseconds per timestamp tick, or `None` when the queue has no timestamps.
    pub(crate) timestamp_period_ns: Option<f32>,
    device_name: String,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    messages: MessageLog,
    instance: ash::Instance,
    _entry: ash::Entry,
}

impl Gpu {
    pub fn new(options: GpuOptions) -> Result<Self> {
        // SAFETY: loading the system Vulkan loader; no other code depends on its global state.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| Error::Loader(e.to_string()))?;
        let messages: MessageLog = Arc::new(Mutex::new(Vec::new()));
        let app_info = vk::ApplicationInfo::default()
            .application_name(c"patchex-scene")
            .api_version(vk::API_VERSION_1_3);
        let layers: Vec<*const c_char> = if options.validation {
            vec![VALIDATION_LAYER.as_ptr()]
        } else {
            Vec::new()
        };
        let extensions: Vec<*const c_char> = if options.validation {
            vec![
                ash::ext::debug_utils::NAME.as_ptr(),
                ash::ext::validation_features::NAME.as_ptr(),
            ]
        } else {
            Vec::new()
        };
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
        let mut instance_messenger = messenger_info(&messages);
        let mut instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if options.validation {
            instance_info = instance_info
                .push_next(&mut validation_features)
                .push_next(&mut instance_messenger);
        }
        // SAFETY: every pointer in `instance_info` outlives the call.
        let instance =
            unsafe { entry.create_instance(&instance_info, None) }.vk("vkCreateInstance")?;

        let messenger = if options.validation {
            let debug_utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
            // SAFETY: the callback's user data (`messages`) lives as long as `Gpu`.
            let handle = unsafe {
                debug_utils.create_debug_utils_messenger(&messenger_info(&messages), None)
            }
            .vk("vkCreateDebugUtilsMessengerEXT")?;
            Some((debug_utils, handle))
        } else {
            None
        };

        let (physical, queue_family) = pick_physical_device(&instance)?;
        // SAFETY: `physical` was enumerated from `instance`.
        let (memory_properties, properties) = unsafe {
            (
                instance.get_physical_device_memory_properties(physical),
                instance.get_physical_device_properties(physical),
            )
        };
        // SAFETY: `physical` comes from `instance`.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let timestamp_period_ns = (families[queue_family as usize].timestamp_valid_bits > 0)
            .then_some(properties.limits.timestamp_period);
        let device_name = properties
            .device_name_as_c_str()
            .map(|name| name.to_string_lossy().into_owned())
            .unwrap_or_default();

        let priorities = [1.0f32];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut vulkan13 = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true);
        let device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .push_next(&mut vulkan13);
        // SAFETY: `physical` supports Vulkan 1.3, which makes dynamic rendering mandatory.
        let device =
            unsafe { instance.create_device(physical, &device_info, None) }.vk("vkCreateDevice")?;
        // SAFETY: one queue of `queue_family` was requested above.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let command_pool =
            unsafe { device.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;

        Ok(Self {
            device,
            queue,
            command_pool,
            memory_properties,
            timestamp_period_ns,
            device_name,
            messenger,
            messages,
            instance,
            _entry: entry,
        })
    }

    pub fn device_name(&self) -> &str {
        &self.device_name
    }

    /// Returns and clears the validation messages seen so far (empty without validation).
    pub fn take_validation_messages(&self) -> Vec<String> {
        self.messages
            .lock()
            .map(|mut messages| std::mem::take(&mut *messages))
            .unwrap_or_default()
    }

    pub(crate) fn create_shader_module(&self, spirv: &[u8]) -> Result<vk::ShaderModule> {
        let words: Vec<u32> = spirv
            .chunks_exact(4)
            .map(|chunk| u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]))
            .collect();
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `words` is SPIR-V validated by naga at build time.
        unsafe { self.device.create_shader_module(&info, None) }.vk("vkCreateShaderModule")
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: owners of GPU resources hold an `Arc<Gpu>` and release them first, so nothing
        // created from this device is alive here.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_device(None);
            if let Some((debug_utils, messenger)) = self.messenger.take() {
                debug_utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
        // Teardown messages (leaked objects, say) arrive after any caller could collect them.
        for message in self.take_validation_messages() {
            eprintln!("validation message at device teardown: {message}");
        }
    }
}

/// Prefers a discrete GPU, then integrated, then anything else (lavapipe is a CPU device).
fn pick_physical_device(instance: &ash::Instance) -> Result<(vk::PhysicalDevice, u32)> {
    // SAFETY: plain queries on a valid instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let rank = |kind: vk::PhysicalDeviceType| match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        _ => 3,
    };
    let mut candidates = Vec::new();
    for physical in devices {
        // SAFETY: `physical` comes from `instance`.
        let properties = unsafe { instance.get_physical_device_properties(physical) };
        if properties.api_version < vk::API_VERSION_1_3 {
            continue;
        }
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        if let Some(family) = families.iter().position(|f| f.queue_flags.contains(wanted)) {
            candidates.push((rank(properties.device_type), physical, family as u32));
        }
    }
    candidates.sort_by_key(|(rank, _, _)| *rank);
    candidates
        .first()
        .map(|&(_, physical, family)| (physical, family))
        .ok_or(Error::NoDevice)
}
