//! What the integration tests share: the analytic scene, and a rig that plays the engine —
//! its own Vulkan device and images, the patchex library loaded through libloading, and the
//! descriptors an engine would fill in.
#![allow(dead_code)]

pub mod pipeline;
pub mod rendered;
pub mod scene;

use std::ptr;

use ash::vk;
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::ffi::PatchexContext;
use patchex::loader::PatchexLibrary;
use patchex::reference::Image;
use patchex_harness::intercept::Intercept;
use patchex_harness::{Engine, EngineImage, EngineOptions};
use patchex_scene::dataset::SunInfo;

use scene::Frame;

pub struct Rig {
    pub engine: Engine,
    pub library: PatchexLibrary,
    pub context: *mut PatchexContext,
    /// Present when the plugin was handed the intercepting function table.
    pub intercept: Option<Intercept>,
}

impl Rig {
    /// As [`Engine::create_info`], with the plugin loading Vulkan through `intercept`.
    pub fn create_info_through(
        engine: &Engine,
        intercept: &Intercept,
        max_width: u32,
        max_height: u32,
    ) -> PatchexCreateInfo {
        let mut info = engine.create_info(max_width, max_height);
        info.get_instance_proc_addr = Some(intercept.get_instance_proc_addr());
        info.get_device_proc_addr = Some(intercept.get_device_proc_addr());
        info
    }

    /// An engine with validation and a patchex context for frames up to `max_width` x `max_height`.
    pub fn new(max_width: u32, max_height: u32) -> Self {
        Self::with_options(max_width, max_height, &EngineOptions::default())
    }

    pub fn with_options(max_width: u32, max_height: u32, options: &EngineOptions) -> Self {
        Self::configured(max_width, max_height, options, |_| {})
    }

    /// A rig whose plugin loads Vulkan through an [`Intercept`], which counts its objects and
    /// can fail its creation calls.
    pub fn intercepted(max_width: u32, max_height: u32) -> Self {
        Self::intercepted_with_options(max_width, max_height, &EngineOptions::default())
    }

    pub fn intercepted_with_options(
        max_width: u32,
        max_height: u32,
        options: &EngineOptions,
    ) -> Self {
        let engine = Engine::new(options).expect("a Vulkan device");
        let intercept = Intercept::install(&engine);
        Self::on_engine(engine, Some(intercept), max_width, max_height)
    }

    /// An intercepted rig whose create info the test edits first.
    pub fn intercepted_with_create_info(
        max_width: u32,
        max_height: u32,
        edit: impl FnOnce(&mut PatchexCreateInfo),
    ) -> Self {
        let engine = Engine::new(&EngineOptions::default()).expect("a Vulkan device");
        let intercept = Intercept::install(&engine);
        Self::on_engine_with(engine, Some(intercept), max_width, max_height, edit)
    }

    /// A rig whose create info the test edits first (a preset, a chain).
    pub fn with_create_info(
        max_width: u32,
        max_height: u32,
        edit: impl FnOnce(&mut PatchexCreateInfo),
    ) -> Self {
        Self::configured(max_width, max_height, &EngineOptions::default(), edit)
    }

    /// A rig on an engine made with `options`, whose create info the caller edits first.
    pub fn configured(
        max_width: u32,
        max_height: u32,
        options: &EngineOptions,
        edit: impl FnOnce(&mut PatchexCreateInfo),
    ) -> Self {
        let engine = Engine::new(options).expect("a Vulkan device");
        Self::on_engine_with(engine, None, max_width, max_height, edit)
    }

    fn on_engine(
        engine: Engine,
        intercept: Option<Intercept>,
        max_width: u32,
        max_height: u32,
    ) -> Self {
        Self::on_engine_with(engine, intercept, max_width, max_height, |_| {})
    }

    fn on_engine_with(
        engine: Engine,
        intercept: Option<Intercept>,
        max_width: u32,
        max_height: u32,
        edit: impl FnOnce(&mut PatchexCreateInfo),
    ) -> Self {
        let library = open_library();
        let mut info = match &intercept {
            Some(intercept) => Self::create_info_through(&engine, intercept, max_width, max_height),
            None => engine.create_info(max_width, max_height),
        };
        edit(&mut info);
        let context = create(&library, &info).unwrap_or_else(|(_, message)| panic!("{message}"));
        engine.assert_validation_clean();
        Self {
            engine,
            library,
            context,
            intercept,
        }
    }

    pub fn last_error(&self) -> String {
        // SAFETY: the rig's context is live.
        unsafe { self.library.last_error_message(self.context) }
    }

    pub fn submit(&self, cmd: vk::CommandBuffer, desc: &PatchexFrameDesc) -> PatchexResult {
        // SAFETY: live context; the descriptor's images live until the command buffer completes.
        unsafe { (self.library.submit_gbuffers)(self.context, cmd, desc) }
    }

    pub fn extrapolate(
        &self,
        cmd: vk::CommandBuffer,
        desc: &PatchexExtrapolateDesc,
    ) -> PatchexResult {
        // SAFETY: as for `submit`.
        unsafe { (self.library.extrapolate)(self.context, cmd, desc) }
    }

    /// `submit`, which must succeed; the library's message otherwise.
    pub fn submit_ok(&self, cmd: vk::CommandBuffer, desc: &PatchexFrameDesc) {
        assert_eq!(
            self.submit(cmd, desc),
            PatchexResult::Success,
            "{}",
            self.last_error()
        );
    }

    /// `extrapolate`, which must succeed; the library's message otherwise.
    pub fn extrapolate_ok(&self, cmd: vk::CommandBuffer, desc: &PatchexExtrapolateDesc) {
        assert_eq!(
            self.extrapolate(cmd, desc),
            PatchexResult::Success,
            "{}",
            self.last_error()
        );
    }

    pub fn stats(&self, frame_index: u64) -> (PatchexResult, PatchexFrameStats) {
        // SAFETY: zeroed stats are a valid PatchexFrameStats bit pattern.
        let mut stats: PatchexFrameStats = unsafe { std::mem::zeroed() };
        stats.header =
            PatchexStructHeader::of::<PatchexFrameStats>(PATCHEX_STRUCT_TYPE_FRAME_STATS);
        // SAFETY: live context, writable stats.
        let result =
            unsafe { (self.library.get_frame_stats)(self.context, frame_index, &mut stats) };
        (result, stats)
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        // SAFETY: every submission was waited on; the context is not used again.
        unsafe {
            self.engine
                .device
                .device_wait_idle()
                .expect("vkDeviceWaitIdle");
            (self.library.destroy)(self.context);
        }
        if !std::thread::panicking() {
            self.engine.assert_validation_clean();
        }
    }
}

/// Runs `command`, fails the test with its output unless it succeeds, and returns its output.
pub fn run(command: &mut std::process::Command, what: &str) -> String {
    let output = command.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(output.status.success(), "{what} failed:\n{text}");
    text
}

/// Installs the library built for these tests into `prefix` with scripts/install.sh, as a C or
/// C++ user installs it.
pub fn install(root: &std::path::Path, prefix: &std::path::Path) {
    let library = PatchexLibrary::beside_current_exe().expect("the patchex cdylib is built");
    run(
        std::process::Command::new(root.join("scripts/install.sh"))
            .arg(prefix)
            .arg(library),
        "scripts/install.sh",
    );
}

/// `pkg-config --cflags --libs patchex` for a library installed into `prefix`.
pub fn pkg_config_flags(prefix: &std::path::Path) -> String {
    run(
        std::process::Command::new("pkg-config")
            .args(["--cflags", "--libs", "patchex"])
            .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig")),
        "pkg-config",
    )
}

/// The patchex shared library built from this tree, loaded as an engine loads it.
pub fn open_library() -> PatchexLibrary {
    let path = PatchexLibrary::beside_current_exe().expect("the patchex cdylib is built");
    // SAFETY: the library was built from this source tree.
    unsafe { PatchexLibrary::open(&path) }.expect("patchex loads")
}

/// `patchex_create`; on failure, its result and message.
pub fn create(
    library: &PatchexLibrary,
    info: &PatchexCreateInfo,
) -> Result<*mut PatchexContext, (PatchexResult, String)> {
    let mut context = ptr::null_mut();
    // SAFETY: valid create info and out pointer.
    let result = unsafe { (library.create)(info, &mut context) };
    if result == PatchexResult::Success {
        return Ok(context);
    }
    // SAFETY: NULL asks for this thread's last error.
    Err((result, unsafe { library.last_error_message(ptr::null()) }))
}

/// Frame `index` of the analytic scene's moving sphere and its halfway target, as engine images.
pub fn frame_pair(engine: &Engine, width: u32, height: u32, index: u64) -> (GpuFrame, GpuFrame) {
    let scene = scene::Scene::new(width as usize, height as usize);
    let time = index as f32 / 30.0;
    let source = scene.render(time, glam::Vec2::ZERO, time - 1.0 / 30.0);
    let target = scene.render(time + 1.0 / 60.0, glam::Vec2::ZERO, time);
    (
        GpuFrame::upload(engine, &source),
        GpuFrame::upload(engine, &target),
    )
}

/// Whether two images hold the same values bit for bit.
pub fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// An engine image holding `image`'s values, left in `layout`.
pub fn upload(
    engine: &Engine,
    image: &Image,
    format: vk::Format,
    layout: vk::ImageLayout,
) -> EngineImage {
    let mut usage = vk::ImageUsageFlags::SAMPLED;
    if layout == vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL {
        usage |= vk::ImageUsageFlags::COLOR_ATTACHMENT;
    }
    let gpu = EngineImage::new(
        engine,
        format,
        image.width as u32,
        image.height as u32,
        usage,
    );
    gpu.upload(engine, &image.data, layout);
    gpu
}

/// One instant's G-buffers as engine images, each with the layout the engine keeps it in.
pub struct GpuFrame {
    pub color: EngineImage,
    pub base_color: EngineImage,
    pub material: EngineImage,
    pub depth: EngineImage,
    pub normal: EngineImage,
    pub stencil: EngineImage,
    pub motion: EngineImage,
    pub shadow_mask: EngineImage,
    pub color_without_dynamic_shadows: EngineImage,
    pub sun_visibility: EngineImage,
    pub static_visibility: EngineImage,
    pub camera: PatchexCamera,
    pub width: u32,
    pub height: u32,
}

/// Layouts the tests' engine keeps its images in: a mix, to exercise the plugin's transitions.
pub const COLOR_LAYOUT: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
pub const GBUFFER_LAYOUT: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
pub const DEPTH_LAYOUT: vk::ImageLayout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
pub const MOTION_LAYOUT: vk::ImageLayout = vk::ImageLayout::GENERAL;
pub const OUTPUT_LAYOUT: vk::ImageLayout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;

impl GpuFrame {
    /// Every G-buffer in a 32-bit float format.
    pub fn upload(engine: &Engine, frame: &Frame) -> Self {
        use vk::Format as F;
        Self::upload_as(engine, frame, F::R32G32B32A32_SFLOAT, F::R32G32_SFLOAT)
    }

    /// Colour, base colour, material, normals and motion vectors in half floats, as many
    /// engines keep them (depth stays 32-bit).
    pub fn upload_half(engine: &Engine, frame: &Frame) -> Self {
        use vk::Format as F;
        Self::upload_as(engine, frame, F::R16G16B16A16_SFLOAT, F::R16G16_SFLOAT)
    }

    fn upload_as(engine: &Engine, frame: &Frame, rgba: vk::Format, rg: vk::Format) -> Self {
        use vk::Format as F;
        Self {
            color: upload(engine, &frame.color, rgba, COLOR_LAYOUT),
            base_color: upload(engine, &frame.base_color, rgba, GBUFFER_LAYOUT),
            material: upload(engine, &frame.material, rgba, GBUFFER_LAYOUT),
            depth: upload(engine, &frame.depth, F::R32_SFLOAT, DEPTH_LAYOUT),
            normal: upload(engine, &frame.normal, rgba, GBUFFER_LAYOUT),
            stencil: upload(engine, &frame.stencil, F::R8_UINT, GBUFFER_LAYOUT),
            motion: upload(engine, &frame.motion, rg, MOTION_LAYOUT),
            shadow_mask: upload(engine, &frame.shadow_mask, F::R32_SFLOAT, GBUFFER_LAYOUT),
            color_without_dynamic_shadows: upload(
                engine,
                &frame.color_without_dynamic_shadows,
                rgba,
                GBUFFER_LAYOUT,
            ),
            sun_visibility: upload(engine, &frame.sun_visibility, F::R32_SFLOAT, GBUFFER_LAYOUT),
            static_visibility: upload(
                engine,
                &frame.static_visibility,
                F::R32_SFLOAT,
                GBUFFER_LAYOUT,
            ),
            camera: frame.camera,
            width: frame.color.width as u32,
            height: frame.color.height as u32,
        }
    }

    pub fn geometry(&self) -> PatchexGeometry {
        PatchexGeometry {
            depth: self.depth.describe(DEPTH_LAYOUT),
            normal: self.normal.describe(GBUFFER_LAYOUT),
            normal_encoding: PATCHEX_NORMAL_SIGNED,
            stencil: self.stencil.describe(GBUFFER_LAYOUT),
            motion_vectors: self.motion.describe(MOTION_LAYOUT),
            motion_vector_scale: [1.0, 1.0],
            camera: self.camera,
        }
    }

    pub fn frame_desc(&self, frame_index: u64, queue_family_index: u32) -> PatchexFrameDesc {
        PatchexFrameDesc {
            header: PatchexStructHeader::of::<PatchexFrameDesc>(PATCHEX_STRUCT_TYPE_FRAME_DESC),
            frame_index,
            reset: 0,
            queue_family_index,
            width: self.width,
            height: self.height,
            color: self.color.describe(COLOR_LAYOUT),
            base_color: self.base_color.describe(GBUFFER_LAYOUT),
            material: self.material.describe(GBUFFER_LAYOUT),
            geometry: self.geometry(),
        }
    }

    /// The frame's shadow input, to chain on its frame desc.
    pub fn shadow_input(&self) -> PatchexShadowInput {
        PatchexShadowInput {
            header: PatchexStructHeader::of::<PatchexShadowInput>(PATCHEX_STRUCT_TYPE_SHADOW_INPUT),
            mask: self.shadow_mask.describe(GBUFFER_LAYOUT),
            color_without_dynamic_shadows: self
                .color_without_dynamic_shadows
                .describe(GBUFFER_LAYOUT),
        }
    }

    /// `sun` as a PatchexSunLight with this frame's visibility: through every caster, or
    /// through static casters alone for a frame that goes `with_shadow_input`.
    pub fn sun_light(&self, sun: &SunInfo, with_shadow_input: bool) -> PatchexSunLight {
        let visibility = if with_shadow_input {
            &self.static_visibility
        } else {
            &self.sun_visibility
        };
        PatchexSunLight {
            header: PatchexStructHeader::of::<PatchexSunLight>(PATCHEX_STRUCT_TYPE_SUN_LIGHT),
            direction: sun.direction,
            illuminance: sun.illuminance,
            visibility: visibility.describe(GBUFFER_LAYOUT),
        }
    }

    pub fn extrapolate_desc(
        &self,
        output: &EngineImage,
        alpha: f32,
        queue_family_index: u32,
    ) -> PatchexExtrapolateDesc {
        PatchexExtrapolateDesc {
            header: PatchexStructHeader::of::<PatchexExtrapolateDesc>(
                PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC,
            ),
            queue_family_index,
            alpha,
            width: self.width,
            height: self.height,
            base_color: self.base_color.describe(GBUFFER_LAYOUT),
            material: self.material.describe(GBUFFER_LAYOUT),
            geometry: self.geometry(),
            output: output.describe(OUTPUT_LAYOUT),
        }
    }
}

/// The engine's output image, R16G16B16A16_SFLOAT with storage usage, in OUTPUT_LAYOUT.
pub fn output_image(engine: &Engine, width: u32, height: u32) -> EngineImage {
    output_image_as(engine, vk::Format::R16G16B16A16_SFLOAT, width, height)
}

/// An output image of `format`, in OUTPUT_LAYOUT: storage usage for RGBA16F, which the plugin
/// writes from a shader; the other formats are blitted (the harness gives every image transfer
/// usage).
pub fn output_image_as(
    engine: &Engine,
    format: vk::Format,
    width: u32,
    height: u32,
) -> EngineImage {
    let mut usage = vk::ImageUsageFlags::SAMPLED;
    if format == vk::Format::R16G16B16A16_SFLOAT {
        usage |= vk::ImageUsageFlags::STORAGE;
    }
    let output = EngineImage::new(engine, format, width, height, usage);
    output.upload(
        engine,
        &vec![0.0; (width * height * 4) as usize],
        OUTPUT_LAYOUT,
    );
    output
}
