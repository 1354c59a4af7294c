//! The engine's Vulkan objects, seen through function tables loaded from the engine's own
//! `vkGetInstanceProcAddr`/`vkGetDeviceProcAddr`. The plugin never creates or destroys them.

use std::ffi::{c_char, CStr};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::abi::PatchexCreateInfo;
use crate::error::{bail, Result};

/// Device-level commands the plugin calls. Checked at creation so that a device whose driver
/// lacks one fails `patchex_create` cleanly instead of calling a null pointer later.
const REQUIRED_DEVICE_COMMANDS: &[&CStr] = &[
    c"vkCreateImage",
    c"vkDestroyImage",
    c"vkCreateImageView",
    c"vkDestroyImageView",
    c"vkGetImageMemoryRequirements",
    c"vkBindImageMemory",
    c"vkCreateBuffer",
    c"vkDestroyBuffer",
    c"vkGetBufferMemoryRequirements",
    c"vkBindBufferMemory",
    c"vkAllocateMemory",
    c"vkFreeMemory",
    c"vkMapMemory",
    c"vkUnmapMemory",
    c"vkCreateShaderModule",
    c"vkDestroyShaderModule",
    c"vkCreateComputePipelines",
    c"vkDestroyPipeline",
    c"vkCreatePipelineLayout",
    c"vkDestroyPipelineLayout",
    c"vkCreateDescriptorSetLayout",
    c"vkDestroyDescriptorSetLayout",
    c"vkCreateDescriptorPool",
    c"vkDestroyDescriptorPool",
    c"vkAllocateDescriptorSets",
    c"vkUpdateDescriptorSets",
    c"vkCreateQueryPool",
    c"vkDestroyQueryPool",
    c"vkGetQueryPoolResults",
    c"vkCmdBindPipeline",
    c"vkCmdBindDescriptorSets",
    c"vkCmdPushConstants",
    c"vkCmdDispatch",
    c"vkCmdDispatchIndirect",
    c"vkCmdPipelineBarrier",
    c"vkCmdResetQueryPool",
    c"vkCmdWriteTimestamp",
    c"vkCmdFillBuffer",
    c"vkCmdCopyImage",
];

/// The engine's instance, physical device and device, with the facts the plugin checks per call.
pub struct Gpu {
    pub instance: ash::Instance,
    pub physical_device: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family_index: u32,
    /// Nanoseconds per timestamp tick, or `None` when the queue family writes no timestamps.
    pub timestamp_period_ns: Option<f64>,
    pub timestamp_valid_mask: u64,
    /// The larger of the storage- and uniform-buffer offset alignments: the counters buffer
    /// binds ranges of both kinds.
    pub min_buffer_offset_alignment: u64,
}

impl Gpu {
    /// # Safety
    /// The handles in `info` must be live objects of one Vulkan instance, as the API requires.
    pub unsafe fn load(info: &PatchexCreateInfo) -> Result<Self> {
        let Some(get_instance_proc_addr) = info.get_instance_proc_addr else {
            bail!(
                ErrorNullPointer,
                "PatchexCreateInfo.get_instance_proc_addr is null"
            );
        };
        if info.instance == vk::Instance::null() {
            bail!(
                ErrorNullPointer,
                "PatchexCreateInfo.instance is VK_NULL_HANDLE"
            );
        }
        if info.physical_device == vk::PhysicalDevice::null() {
            bail!(
                ErrorNullPointer,
                "PatchexCreateInfo.physical_device is VK_NULL_HANDLE"
            );
        }
        if info.device == vk::Device::null() {
            bail!(
                ErrorNullPointer,
                "PatchexCreateInfo.device is VK_NULL_HANDLE"
            );
        }
        let static_fn = ash::StaticFn {
            get_instance_proc_addr,
        };
        let instance = ash::Instance::load(&static_fn, info.instance);
        let get_device_proc_addr = match info.get_device_proc_addr {
            Some(get_device_proc_addr) => get_device_proc_addr,
            None => instance.fp_v1_0().get_device_proc_addr,
        };
        let lookup =
            |name: &CStr| get_device_proc_addr(info.device, name.as_ptr() as *const c_char);
        if let Some(missing) = REQUIRED_DEVICE_COMMANDS
            .iter()
            .find(|name| lookup(name).is_none())
        {
            bail!(
                ErrorMissingDeviceFeature,
                "the device does not provide {}",
                missing.to_string_lossy()
            );
        }
        let device = ash::Device::load_with(
            |name| {
                std::mem::transmute::<vk::PFN_vkVoidFunction, *const std::ffi::c_void>(lookup(name))
            },
            info.device,
        );

        let families = instance.get_physical_device_queue_family_properties(info.physical_device);
        let Some(family) = families.get(info.queue_family_index as usize) else {
            bail!(
                ErrorInvalidArgument,
                "queue_family_index {} does not exist (the device has {} families)",
                info.queue_family_index,
                families.len()
            );
        };
        if !family.queue_flags.contains(vk::QueueFlags::COMPUTE) {
            bail!(
                ErrorMissingDeviceFeature,
                "queue family {} does not support compute ({:?})",
                info.queue_family_index,
                family.queue_flags
            );
        }
        let properties = instance.get_physical_device_properties(info.physical_device);
        let timestamps =
            family.timestamp_valid_bits > 0 && properties.limits.timestamp_period > 0.0;
        let timestamp_valid_mask = match family.timestamp_valid_bits {
            64.. => u64::MAX,
            bits => (1u64 << bits) - 1,
        };
        Ok(Self {
            instance,
            physical_device: info.physical_device,
            device,
            queue_family_index: info.queue_family_index,
            timestamp_period_ns: timestamps.then_some(properties.limits.timestamp_period as f64),
            timestamp_valid_mask,
            min_buffer_offset_alignment: properties
                .limits
                .min_storage_buffer_offset_alignment
                .max(properties.limits.min_uniform_buffer_offset_alignment),
        })
    }

    /// The allocator of the plugin's own images and buffers on this device.
    pub fn allocator(&self) -> Result<Allocator> {
        Ok(Allocator::new(&AllocatorCreateDesc {
            instance: self.instance.clone(),
            device: self.device.clone(),
            physical_device: self.physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?)
    }

    /// Optimal-tiling features of `format` on this device.
    pub fn format_features(&self, format: vk::Format) -> vk::FormatFeatureFlags {
        // SAFETY: the physical device outlives the context (API contract).
        unsafe {
            self.instance
                .get_physical_device_format_properties(self.physical_device, format)
                .optimal_tiling_features
        }
    }
}
