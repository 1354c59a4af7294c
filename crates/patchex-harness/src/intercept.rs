//! A shim in the function table an engine hands to patchex: the plugin loads every Vulkan
//! function through `get_instance_proc_addr`/`get_device_proc_addr`, so wrapping those two sees
//! every object it creates and destroys and every dispatch and barrier it records. Tests and the
//! soak use it to count the plugin's live objects and memory, to make a chosen creation call fail
//! (allocation failure, injected), to hide format features from it (a device that lacks them),
//! and to count its commands. Nothing in the library knows.
//!
//! State is kept per `VkDevice` (per `VkPhysicalDevice` for format features), so tests running
//! in parallel threads of one process do not see each other's objects.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::ffi::{c_char, CStr};
use std::sync::{Mutex, MutexGuard, OnceLock};

use ash::vk;
use ash::vk::Handle;

use crate::Engine;

/// The kinds of object the plugin may create.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ObjectKind {
    Image,
    ImageView,
    Buffer,
    Memory,
    ShaderModule,
    Pipeline,
    PipelineLayout,
    DescriptorSetLayout,
    DescriptorPool,
    /// Allocated from a pool and freed with it: counted as calls, never as live objects.
    DescriptorSet,
    QueryPool,
}

/// What the plugin holds on one device now.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LiveObjects {
    pub counts: BTreeMap<ObjectKind, usize>,
    /// Sum of the sizes of live `vkAllocateMemory` allocations.
    pub memory_bytes: u64,
}

impl LiveObjects {
    pub fn total(&self) -> usize {
        self.counts.values().sum()
    }
}

type VoidFunction = vk::PFN_vkVoidFunction;

/// Declares the wrapped device functions once: the table of real pointers, its loader, and the
/// lookup that hands out the wrappers (each wrapper is the function named like its field).
macro_rules! wrapped_device_functions {
    ($($field:ident: $pfn:ty = $vk_name:literal;)*) => {
        #[derive(Clone, Copy)]
        struct RealFunctions {
            $($field: $pfn,)*
        }

        impl RealFunctions {
            /// # Safety
            /// `device` is live and `get_device_proc_addr` is its loader's.
            unsafe fn load(
                get_device_proc_addr: vk::PFN_vkGetDeviceProcAddr,
                device: vk::Device,
            ) -> Self {
                Self {
                    $($field: std::mem::transmute::<unsafe extern "system" fn(), $pfn>(
                        get_device_proc_addr(device, $vk_name.as_ptr())
                            .expect("a core Vulkan device function"),
                    ),)*
                }
            }
        }

        fn device_wrapper(name: &CStr) -> VoidFunction {
            $(if name == $vk_name {
                // SAFETY: the wrapper has exactly the signature of the function it stands for.
                return Some(unsafe {
                    std::mem::transmute::<$pfn, unsafe extern "system" fn()>($field as $pfn)
                });
            })*
            None
        }
    };
}

wrapped_device_functions! {
    create_image: vk::PFN_vkCreateImage = c"vkCreateImage";
    destroy_image: vk::PFN_vkDestroyImage = c"vkDestroyImage";
    create_image_view: vk::PFN_vkCreateImageView = c"vkCreateImageView";
    destroy_image_view: vk::PFN_vkDestroyImageView = c"vkDestroyImageView";
    create_buffer: vk::PFN_vkCreateBuffer = c"vkCreateBuffer";
    destroy_buffer: vk::PFN_vkDestroyBuffer = c"vkDestroyBuffer";
    allocate_memory: vk::PFN_vkAllocateMemory = c"vkAllocateMemory";
    free_memory: vk::PFN_vkFreeMemory = c"vkFreeMemory";
    create_shader_module: vk::PFN_vkCreateShaderModule = c"vkCreateShaderModule";
    destroy_shader_module: vk::PFN_vkDestroyShaderModule = c"vkDestroyShaderModule";
    create_compute_pipelines: vk::PFN_vkCreateComputePipelines = c"vkCreateComputePipelines";
    destroy_pipeline: vk::PFN_vkDestroyPipeline = c"vkDestroyPipeline";
    create_pipeline_layout: vk::PFN_vkCreatePipelineLayout = c"vkCreatePipelineLayout";
    destroy_pipeline_layout: vk::PFN_vkDestroyPipelineLayout = c"vkDestroyPipelineLayout";
    create_descriptor_set_layout: vk::PFN_vkCreateDescriptorSetLayout =
        c"vkCreateDescriptorSetLayout";
    destroy_descriptor_set_layout: vk::PFN_vkDestroyDescriptorSetLayout =
        c"vkDestroyDescriptorSetLayout";
    create_descriptor_pool: vk::PFN_vkCreateDescriptorPool = c"vkCreateDescriptorPool";
    destroy_descriptor_pool: vk::PFN_vkDestroyDescriptorPool = c"vkDestroyDescriptorPool";
    allocate_descriptor_sets: vk::PFN_vkAllocateDescriptorSets = c"vkAllocateDescriptorSets";
    create_query_pool: vk::PFN_vkCreateQueryPool = c"vkCreateQueryPool";
    destroy_query_pool: vk::PFN_vkDestroyQueryPool = c"vkDestroyQueryPool";
    cmd_dispatch: vk::PFN_vkCmdDispatch = c"vkCmdDispatch";
    cmd_dispatch_indirect: vk::PFN_vkCmdDispatchIndirect = c"vkCmdDispatchIndirect";
    cmd_pipeline_barrier: vk::PFN_vkCmdPipelineBarrier = c"vkCmdPipelineBarrier";
}

/// The commands the plugin recorded into one command buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecordedCommands {
    /// vkCmdDispatch and vkCmdDispatchIndirect.
    pub dispatches: u32,
    pub barriers: u32,
}

/// What the plugin recorded, per command buffer.
static RECORDED: Mutex<Option<HashMap<u64, RecordedCommands>>> = Mutex::new(None);

/// Devices by their loader dispatch key.
static DEVICES_BY_KEY: Mutex<Option<HashMap<usize, vk::Device>>> = Mutex::new(None);

/// The key the loader gives a dispatchable handle: its first word points to the dispatch table,
/// which a device shares with its command buffers (the loader and driver interface).
///
/// # Safety
/// `handle` is a live dispatchable handle.
unsafe fn dispatch_key(handle: u64) -> usize {
    *(handle as *const usize)
}

/// Counts a command recorded into `cmd` and returns the real functions of its device.
///
/// # Safety
/// `cmd` is a live command buffer of an intercepted device.
unsafe fn count(cmd: vk::CommandBuffer, add: impl FnOnce(&mut RecordedCommands)) -> RealFunctions {
    add(lock(&RECORDED)
        .get_or_insert_with(HashMap::new)
        .entry(cmd.as_raw())
        .or_default());
    let device = lock(&DEVICES_BY_KEY)
        .as_ref()
        .and_then(|devices| devices.get(&dispatch_key(cmd.as_raw())).copied())
        .expect("a command buffer of an intercepted device");
    real(device)
}

unsafe extern "system" fn cmd_dispatch(cmd: vk::CommandBuffer, x: u32, y: u32, z: u32) {
    (count(cmd, |c| c.dispatches += 1).cmd_dispatch)(cmd, x, y, z)
}

unsafe extern "system" fn cmd_dispatch_indirect(
    cmd: vk::CommandBuffer,
    buffer: vk::Buffer,
    offset: vk::DeviceSize,
) {
    (count(cmd, |c| c.dispatches += 1).cmd_dispatch_indirect)(cmd, buffer, offset)
}

#[allow(clippy::too_many_arguments)]
unsafe extern "system" fn cmd_pipeline_barrier(
    cmd: vk::CommandBuffer,
    src_stages: vk::PipelineStageFlags,
    dst_stages: vk::PipelineStageFlags,
    dependency: vk::DependencyFlags,
    memory_count: u32,
    memory: *const vk::MemoryBarrier<'_>,
    buffer_count: u32,
    buffers: *const vk::BufferMemoryBarrier<'_>,
    image_count: u32,
    images: *const vk::ImageMemoryBarrier<'_>,
) {
    (count(cmd, |c| c.barriers += 1).cmd_pipeline_barrier)(
        cmd,
        src_stages,
        dst_stages,
        dependency,
        memory_count,
        memory,
        buffer_count,
        buffers,
        image_count,
        images,
    )
}

#[derive(Default)]
struct DeviceState {
    live: HashMap<ObjectKind, HashSet<u64>>,
    memory_sizes: HashMap<u64, u64>,
    /// Kind of every creation call so far, in order.
    calls: Vec<ObjectKind>,
    /// Index (into `calls`) of the creation call to fail.
    fail_call: Option<usize>,
    /// Misuse seen: destroying what is not live.
    errors: Vec<String>,
}

struct Globals {
    get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    get_device_proc_addr: vk::PFN_vkGetDeviceProcAddr,
    get_format_properties: vk::PFN_vkGetPhysicalDeviceFormatProperties,
}

static GLOBALS: OnceLock<Globals> = OnceLock::new();
static REAL: Mutex<Option<HashMap<u64, RealFunctions>>> = Mutex::new(None);
static DEVICES: Mutex<Option<HashMap<u64, DeviceState>>> = Mutex::new(None);
/// Format features hidden per physical device.
static HIDDEN_FEATURES: Mutex<Option<HashMap<(u64, i32), vk::FormatFeatureFlags>>> =
    Mutex::new(None);

fn lock<T>(mutex: &'static Mutex<Option<T>>) -> MutexGuard<'static, Option<T>> {
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn with_state<R>(device: vk::Device, f: impl FnOnce(&mut DeviceState) -> R) -> Option<R> {
    lock(&DEVICES)
        .as_mut()
        .and_then(|devices| devices.get_mut(&device.as_raw()))
        .map(f)
}

fn real(device: vk::Device) -> RealFunctions {
    lock(&REAL)
        .as_ref()
        .and_then(|real| real.get(&device.as_raw()).copied())
        .expect("the device is intercepted")
}

/// Records a creation call; returns the error to inject instead of calling the driver.
fn begin_creation(device: vk::Device, kind: ObjectKind, error: vk::Result) -> Option<vk::Result> {
    with_state(device, |state| {
        let index = state.calls.len();
        state.calls.push(kind);
        (state.fail_call == Some(index)).then_some(error)
    })
    .flatten()
}

fn created(device: vk::Device, kind: ObjectKind, handles: impl IntoIterator<Item = u64>) {
    with_state(device, |state| {
        let live = state.live.entry(kind).or_default();
        live.extend(handles.into_iter().filter(|&h| h != 0));
    });
}

fn destroyed(device: vk::Device, kind: ObjectKind, handle: u64) {
    if handle == 0 {
        return;
    }
    with_state(device, |state| {
        if !state.live.entry(kind).or_default().remove(&handle) {
            state
                .errors
                .push(format!("destroyed {kind:?} {handle:#x}, which is not live"));
        }
        if kind == ObjectKind::Memory {
            state.memory_sizes.remove(&handle);
        }
    });
}

/// One create/destroy pair of wrappers for an object made one at a time.
macro_rules! single_object {
    ($create:ident, $destroy:ident, $kind:ident, $info:ty, $handle:ty, $error:expr) => {
        unsafe extern "system" fn $create(
            device: vk::Device,
            info: *const $info,
            allocator: *const vk::AllocationCallbacks<'_>,
            out: *mut $handle,
        ) -> vk::Result {
            if let Some(error) = begin_creation(device, ObjectKind::$kind, $error) {
                return error;
            }
            let result = (real(device).$create)(device, info, allocator, out);
            if result == vk::Result::SUCCESS {
                created(device, ObjectKind::$kind, [(*out).as_raw()]);
            }
            result
        }

        destroy_wrapper!($destroy, $kind, $handle);
    };
}

/// The wrapper of a vkDestroy*/vkFree* function.
macro_rules! destroy_wrapper {
    ($destroy:ident, $kind:ident, $handle:ty) => {
        unsafe extern "system" fn $destroy(
            device: vk::Device,
            handle: $handle,
            allocator: *const vk::AllocationCallbacks<'_>,
        ) {
            (real(device).$destroy)(device, handle, allocator);
            destroyed(device, ObjectKind::$kind, handle.as_raw());
        }
    };
}

destroy_wrapper!(free_memory, Memory, vk::DeviceMemory);
destroy_wrapper!(destroy_pipeline, Pipeline, vk::Pipeline);

const HOST: vk::Result = vk::Result::ERROR_OUT_OF_HOST_MEMORY;
const DEVICE: vk::Result = vk::Result::ERROR_OUT_OF_DEVICE_MEMORY;

single_object!(
    create_image,
    destroy_image,
    Image,
    vk::ImageCreateInfo<'_>,
    vk::Image,
    DEVICE
);
single_object!(
    create_image_view,
    destroy_image_view,
    ImageView,
    vk::ImageViewCreateInfo<'_>,
    vk::ImageView,
    HOST
);
single_object!(
    create_buffer,
    destroy_buffer,
    Buffer,
    vk::BufferCreateInfo<'_>,
    vk::Buffer,
    DEVICE
);
single_object!(
    create_shader_module,
    destroy_shader_module,
    ShaderModule,
    vk::ShaderModuleCreateInfo<'_>,
    vk::ShaderModule,
    HOST
);
single_object!(
    create_pipeline_layout,
    destroy_pipeline_layout,
    PipelineLayout,
    vk::PipelineLayoutCreateInfo<'_>,
    vk::PipelineLayout,
    HOST
);
single_object!(
    create_descriptor_set_layout,
    destroy_descriptor_set_layout,
    DescriptorSetLayout,
    vk::DescriptorSetLayoutCreateInfo<'_>,
    vk::DescriptorSetLayout,
    HOST
);
single_object!(
    create_descriptor_pool,
    destroy_descriptor_pool,
    DescriptorPool,
    vk::DescriptorPoolCreateInfo<'_>,
    vk::DescriptorPool,
    HOST
);
single_object!(
    create_query_pool,
    destroy_query_pool,
    QueryPool,
    vk::QueryPoolCreateInfo<'_>,
    vk::QueryPool,
    HOST
);

unsafe extern "system" fn allocate_memory(
    device: vk::Device,
    info: *const vk::MemoryAllocateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    out: *mut vk::DeviceMemory,
) -> vk::Result {
    if let Some(error) = begin_creation(device, ObjectKind::Memory, DEVICE) {
        return error;
    }
    let result = (real(device).allocate_memory)(device, info, allocator, out);
    if result == vk::Result::SUCCESS {
        let handle = (*out).as_raw();
        created(device, ObjectKind::Memory, [handle]);
        with_state(device, |state| {
            state.memory_sizes.insert(handle, (*info).allocation_size)
        });
    }
    result
}

unsafe extern "system" fn create_compute_pipelines(
    device: vk::Device,
    cache: vk::PipelineCache,
    count: u32,
    infos: *const vk::ComputePipelineCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    out: *mut vk::Pipeline,
) -> vk::Result {
    if let Some(error) = begin_creation(device, ObjectKind::Pipeline, HOST) {
        // The spec has every output handle set to VK_NULL_HANDLE on failure.
        for i in 0..count as usize {
            *out.add(i) = vk::Pipeline::null();
        }
        return error;
    }
    let result =
        (real(device).create_compute_pipelines)(device, cache, count, infos, allocator, out);
    let handles = (0..count as usize).map(|i| (*out.add(i)).as_raw());
    created(device, ObjectKind::Pipeline, handles.collect::<Vec<_>>());
    result
}

unsafe extern "system" fn allocate_descriptor_sets(
    device: vk::Device,
    info: *const vk::DescriptorSetAllocateInfo<'_>,
    out: *mut vk::DescriptorSet,
) -> vk::Result {
    if let Some(error) = begin_creation(device, ObjectKind::DescriptorSet, HOST) {
        return error;
    }
    (real(device).allocate_descriptor_sets)(device, info, out)
}

unsafe extern "system" fn get_physical_device_format_properties(
    physical_device: vk::PhysicalDevice,
    format: vk::Format,
    out: *mut vk::FormatProperties,
) {
    let globals = GLOBALS.get().expect("installed");
    (globals.get_format_properties)(physical_device, format, out);
    let hidden = lock(&HIDDEN_FEATURES).as_ref().and_then(|hidden| {
        hidden
            .get(&(physical_device.as_raw(), format.as_raw()))
            .copied()
    });
    if let Some(hidden) = hidden {
        (*out).optimal_tiling_features &= !hidden;
        (*out).linear_tiling_features &= !hidden;
    }
}

unsafe extern "system" fn intercepted_get_device_proc_addr(
    device: vk::Device,
    name: *const c_char,
) -> VoidFunction {
    let globals = GLOBALS.get().expect("installed");
    device_wrapper(CStr::from_ptr(name)).or_else(|| (globals.get_device_proc_addr)(device, name))
}

unsafe extern "system" fn intercepted_get_instance_proc_addr(
    instance: vk::Instance,
    name: *const c_char,
) -> VoidFunction {
    let globals = GLOBALS.get().expect("installed");
    match CStr::from_ptr(name).to_bytes() {
        b"vkGetDeviceProcAddr" => Some(std::mem::transmute::<
            vk::PFN_vkGetDeviceProcAddr,
            unsafe extern "system" fn(),
        >(intercepted_get_device_proc_addr)),
        b"vkGetPhysicalDeviceFormatProperties" => {
            Some(std::mem::transmute::<
                vk::PFN_vkGetPhysicalDeviceFormatProperties,
                unsafe extern "system" fn(),
            >(get_physical_device_format_properties))
        }
        _ => device_wrapper(CStr::from_ptr(name))
            .or_else(|| (globals.get_instance_proc_addr)(instance, name)),
    }
}

/// The shim on one engine's device; removed when dropped. Hand the plugin
/// [`Intercept::get_instance_proc_addr`] and [`Intercept::get_device_proc_addr`] instead of the
/// loader's.
pub struct Intercept {
    device: vk::Device,
    physical_device: vk::PhysicalDevice,
}

impl Intercept {
    pub fn install(engine: &Engine) -> Self {
        let loader_gipa = engine.get_instance_proc_addr();
        let instance = engine.instance.handle();
        // SAFETY: looking up core functions through the loader for the engine's live instance.
        let globals = GLOBALS.get_or_init(|| unsafe {
            let lookup =
                |name: &CStr| loader_gipa(instance, name.as_ptr()).expect("a core Vulkan function");
            Globals {
                get_instance_proc_addr: loader_gipa,
                get_device_proc_addr: std::mem::transmute::<
                    unsafe extern "system" fn(),
                    vk::PFN_vkGetDeviceProcAddr,
                >(lookup(c"vkGetDeviceProcAddr")),
                get_format_properties: std::mem::transmute::<
                    unsafe extern "system" fn(),
                    vk::PFN_vkGetPhysicalDeviceFormatProperties,
                >(lookup(
                    c"vkGetPhysicalDeviceFormatProperties",
                )),
            }
        });
        let device = engine.device.handle();
        // SAFETY: the engine's device is live; the loader's vkGetDeviceProcAddr serves it.
        let functions = unsafe { RealFunctions::load(globals.get_device_proc_addr, device) };
        lock(&DEVICES_BY_KEY)
            .get_or_insert_with(HashMap::new)
            // SAFETY: the engine's device is a live dispatchable handle.
            .insert(unsafe { dispatch_key(device.as_raw()) }, device);
        lock(&REAL)
            .get_or_insert_with(HashMap::new)
            .insert(device.as_raw(), functions);
        lock(&DEVICES)
            .get_or_insert_with(HashMap::new)
            .insert(device.as_raw(), DeviceState::default());
        Self {
            device,
            physical_device: engine.physical_device,
        }
    }

    pub fn get_instance_proc_addr(&self) -> vk::PFN_vkGetInstanceProcAddr {
        intercepted_get_instance_proc_addr
    }

    pub fn get_device_proc_addr(&self) -> vk::PFN_vkGetDeviceProcAddr {
        intercepted_get_device_proc_addr
    }

    fn state<R>(&self, f: impl FnOnce(&mut DeviceState) -> R) -> R {
        with_state(self.device, f).expect("installed")
    }

    /// Objects made through the shim and not yet destroyed.
    pub fn live(&self) -> LiveObjects {
        self.state(|state| LiveObjects {
            counts: state
                .live
                .iter()
                .filter(|(_, handles)| !handles.is_empty())
                .map(|(&kind, handles)| (kind, handles.len()))
                .collect(),
            memory_bytes: state.memory_sizes.values().sum(),
        })
    }

    /// Kinds of the creation calls made so far, in order.
    pub fn creation_calls(&self) -> Vec<ObjectKind> {
        self.state(|state| state.calls.clone())
    }

    /// Makes the `n`-th creation call from now (0: the next) fail, as a driver out of memory
    /// would; `None` stops injecting.
    pub fn fail_creation_call(&self, n: Option<usize>) {
        self.state(|state| state.fail_call = n.map(|n| state.calls.len() + n));
    }

    /// Destruction of objects that were not live, seen so far.
    pub fn take_errors(&self) -> Vec<String> {
        self.state(|state| std::mem::take(&mut state.errors))
    }

    /// The dispatches and barriers the plugin recorded into `cmd` since the last call for it.
    pub fn take_recorded(&self, cmd: vk::CommandBuffer) -> RecordedCommands {
        lock(&RECORDED)
            .as_mut()
            .and_then(|recorded| recorded.remove(&cmd.as_raw()))
            .unwrap_or_default()
    }

    /// Makes the physical device report `format` without `features`, as a device that lacks
    /// them would.
    pub fn hide_format_features(&self, format: vk::Format, features: vk::FormatFeatureFlags) {
        lock(&HIDDEN_FEATURES)
            .get_or_insert_with(HashMap::new)
            .insert((self.physical_device.as_raw(), format.as_raw()), features);
    }
}

impl Drop for Intercept {
    fn drop(&mut self) {
        let key = self.device.as_raw();
        // The real functions stay registered: a context destroyed after this still calls them.
        lock(&DEVICES).as_mut().map(|devices| devices.remove(&key));
        let physical = self.physical_device.as_raw();
        if let Some(hidden) = lock(&HIDDEN_FEATURES).as_mut() {
            hidden.retain(|(device, _), _| *device != physical);
        }
    }
}
