//! Turns the engine's descriptors into checked inputs: every image against its role and the
//! frame extent, every camera and enumeration against its range. Nothing is recorded until all
//! of a call's inputs pass, so a rejected call leaves the context and the command buffer as
//! they were.

use ash::vk;
use glam::Vec2;

use crate::abi::*;
use crate::camera::Camera;
use crate::error::{bail, Result};
use crate::passes::highlights::SkyMap;
use crate::vk::device::Gpu;
use crate::vk::image::*;

pub struct GeometryInputs {
    pub depth: ImportedImage,
    pub normal: ImportedImage,
    pub normal_encoding: PatchexNormalEncoding,
    pub stencil: Option<ImportedImage>,
    pub motion_vectors: Option<ImportedImage>,
    pub motion_vector_scale: [f32; 2],
    pub camera: Camera,
}

pub struct SourceInputs {
    pub frame_index: u64,
    pub reset: bool,
    pub extent: vk::Extent2D,
    pub color: ImportedImage,
    pub base_color: ImportedImage,
    pub material: Option<ImportedImage>,
    pub geometry: GeometryInputs,
}

/// A frame's optional shadow input (`PatchexShadowInput`).
pub struct ShadowInputs {
    pub mask: ImportedImage,
    pub color_without_dynamic_shadows: ImportedImage,
}

pub fn shadow(gpu: &Gpu, input: &PatchexShadowInput, extent: vk::Extent2D) -> Result<ShadowInputs> {
    Ok(ShadowInputs {
        mask: ImportedImage::import_required(
            gpu,
            &input.mask,
            &ImageRole::input("PatchexShadowInput.mask", MASK_FORMATS),
            extent,
        )?,
        color_without_dynamic_shadows: ImportedImage::import_required(
            gpu,
            &input.color_without_dynamic_shadows,
            &ImageRole::input(
                "PatchexShadowInput.color_without_dynamic_shadows",
                FLOAT_COLOR_FORMATS,
            ),
            extent,
        )?,
    })
}

/// A frame's optional sun (`PatchexSunLight`), checked: a unit direction and a usable
/// illuminance.
pub struct SunInputs {
    pub direction: glam::Vec3,
    pub illuminance: glam::Vec3,
    pub visibility: ImportedImage,
}

pub fn sun(gpu: &Gpu, input: &PatchexSunLight, extent: vk::Extent2D) -> Result<SunInputs> {
    let direction = glam::Vec3::from_array(input.direction);
    let length = direction.length();
    if !length.is_finite() || length <= f32::MIN_POSITIVE {
        bail!(
            ErrorInvalidArgument,
            "PatchexSunLight.direction {:?} is not a direction: it needs a finite length above 0",
            input.direction
        );
    }
    let illuminance = glam::Vec3::from_array(input.illuminance);
    if !illuminance.is_finite() || illuminance.min_element() < 0.0 {
        bail!(
            ErrorInvalidArgument,
            "PatchexSunLight.illuminance {:?} must be finite and >= 0 in every channel",
            input.illuminance
        );
    }
    Ok(SunInputs {
        direction: direction / length,
        illuminance,
        visibility: ImportedImage::import_required(
            gpu,
            &input.visibility,
            &ImageRole::input("PatchexSunLight.visibility", MASK_FORMATS),
            extent,
        )?,
    })
}

/// A frame's optional sky (`PatchexSkyLight`), checked: its map, square, of a usable side and
/// mips, and how it is laid out.
pub fn sky(gpu: &Gpu, input: &PatchexSkyLight) -> Result<(ImportedImage, SkyMap)> {
    let (width, height) = (input.radiance.width, input.radiance.height);
    if width != height || !(2..=PATCHEX_MAX_SKY_SIDE).contains(&width) {
        bail!(
            ErrorInvalidArgument,
            "PatchexSkyLight.radiance is {width}x{height}: an octahedral map is square, 2 to \
             PATCHEX_MAX_SKY_SIDE ({PATCHEX_MAX_SKY_SIDE}) texels a side"
        );
    }
    let levels = input.mip_levels.max(1);
    if levels > PATCHEX_MAX_SKY_MIPS || width >> (levels - 1) < 2 {
        bail!(
            ErrorInvalidArgument,
            "PatchexSkyLight.mip_levels {} for a map of side {width}: at most \
             PATCHEX_MAX_SKY_MIPS ({PATCHEX_MAX_SKY_MIPS}), and the last mip at least 2 texels \
             a side",
            input.mip_levels
        );
    }
    let mut map = ImportedImage::import_required(
        gpu,
        &input.radiance,
        &ImageRole::input("PatchexSkyLight.radiance", FLOAT_COLOR_FORMATS),
        vk::Extent2D { width, height },
    )?;
    map.mip_levels = levels;
    Ok((
        map,
        SkyMap {
            side: width,
            levels,
        },
    ))
}

/// A frame's optional translucency input (`PatchexTranslucencyInput`), checked.
pub struct TranslucencyInputs {
    pub mask: ImportedImage,
    pub motion_vectors: Option<ImportedImage>,
    pub motion_vector_scale: [f32; 2],
    pub opaque_color: Option<ImportedImage>,
}

pub fn translucency(
    gpu: &Gpu,
    input: &PatchexTranslucencyInput,
    extent: vk::Extent2D,
) -> Result<TranslucencyInputs> {
    let motion_vectors = ImportedImage::import(
        gpu,
        &input.motion_vectors,
        &ImageRole::input("PatchexTranslucencyInput.motion_vectors", MOTION_FORMATS),
        extent,
    )?;
    if motion_vectors.is_some() && !Vec2::from(input.motion_vector_scale).is_finite() {
        bail!(
            ErrorInvalidArgument,
            "PatchexTranslucencyInput.motion_vector_scale must be finite"
        );
    }
    Ok(TranslucencyInputs {
        mask: ImportedImage::import_required(
            gpu,
            &input.mask,
            &ImageRole::input("PatchexTranslucencyInput.mask", MASK_FORMATS),
            extent,
        )?,
        motion_vectors,
        motion_vector_scale: input.motion_vector_scale,
        opaque_color: ImportedImage::import(
            gpu,
            &input.opaque_color,
            &ImageRole::input("PatchexTranslucencyInput.opaque_color", FLOAT_COLOR_FORMATS),
            extent,
        )?,
    })
}

pub struct TargetInputs {
    pub alpha: f32,
    pub extent: vk::Extent2D,
    pub base_color: ImportedImage,
    pub material: Option<ImportedImage>,
    pub geometry: GeometryInputs,
    pub motion_vectors: ImportedImage,
    pub output: ImportedImage,
}

pub fn extent(width: u32, height: u32, max: vk::Extent2D, what: &str) -> Result<vk::Extent2D> {
    if width == 0 || height == 0 {
        bail!(
            ErrorInvalidArgument,
            "{what}: extent {width}x{height} is empty"
        );
    }
    if width > max.width || height > max.height {
        bail!(
            ErrorExtentTooLarge,
            "{what}: extent {width}x{height} exceeds the maximum {}x{} given to patchex_create",
            max.width,
            max.height
        );
    }
    Ok(vk::Extent2D { width, height })
}

pub fn boolean(value: PatchexBool, what: &str) -> Result<bool> {
    match value {
        0 => Ok(false),
        1 => Ok(true),
        other => bail!(
            ErrorInvalidArgument,
            "{what} is {other}; a PatchexBool is 0 or 1"
        ),
    }
}

fn geometry(
    gpu: &Gpu,
    geometry: &PatchexGeometry,
    prefix: &str,
    extent: vk::Extent2D,
) -> Result<GeometryInputs> {
    let name = |field: &str| format!("{prefix}.{field}");
    if geometry.normal_encoding > PATCHEX_NORMAL_UNORM {
        bail!(
            ErrorInvalidArgument,
            "{prefix}.normal_encoding {} is not a PATCHEX_NORMAL_* value",
            geometry.normal_encoding
        );
    }
    if !Vec2::from(geometry.motion_vector_scale).is_finite() {
        bail!(
            ErrorInvalidArgument,
            "{prefix}.motion_vector_scale must be finite"
        );
    }
    Ok(GeometryInputs {
        depth: ImportedImage::import_required(
            gpu,
            &geometry.depth,
            &ImageRole::input(&name("depth"), DEPTH_FORMATS),
            extent,
        )?,
        normal: ImportedImage::import_required(
            gpu,
            &geometry.normal,
            &ImageRole::input(&name("normal"), FLOAT_COLOR_FORMATS),
            extent,
        )?,
        normal_encoding: geometry.normal_encoding,
        stencil: ImportedImage::import(
            gpu,
            &geometry.stencil,
            &ImageRole::input(&name("stencil"), STENCIL_FORMATS),
            extent,
        )?,
        motion_vectors: ImportedImage::import(
            gpu,
            &geometry.motion_vectors,
            &ImageRole::input(&name("motion_vectors"), MOTION_FORMATS),
            extent,
        )?,
        motion_vector_scale: geometry.motion_vector_scale,
        camera: Camera::from_abi(&geometry.camera, &format!("{prefix}.camera"))?,
    })
}

pub fn source(gpu: &Gpu, desc: &PatchexFrameDesc, max: vk::Extent2D) -> Result<SourceInputs> {
    const P: &str = "PatchexFrameDesc";
    let extent = extent(desc.width, desc.height, max, P)?;
    Ok(SourceInputs {
        frame_index: desc.frame_index,
        reset: boolean(desc.reset, "PatchexFrameDesc.reset")?,
        extent,
        color: ImportedImage::import_required(
            gpu,
            &desc.color,
            &ImageRole::input("PatchexFrameDesc.color", FLOAT_COLOR_FORMATS),
            extent,
        )?,
        base_color: ImportedImage::import_required(
            gpu,
            &desc.base_color,
            &ImageRole::input("PatchexFrameDesc.base_color", FLOAT_COLOR_FORMATS),
            extent,
        )?,
        material: ImportedImage::import(
            gpu,
            &desc.material,
            &ImageRole::input("PatchexFrameDesc.material", FLOAT_COLOR_FORMATS),
            extent,
        )?,
        geometry: geometry(gpu, &desc.geometry, "PatchexFrameDesc.geometry", extent)?,
    })
}

pub fn target(gpu: &Gpu, desc: &PatchexExtrapolateDesc, max: vk::Extent2D) -> Result<TargetInputs> {
    const P: &str = "PatchexExtrapolateDesc";
    let extent = extent(desc.width, desc.height, max, P)?;
    if !(desc.alpha.is_finite() && desc.alpha > 0.0 && desc.alpha <= 1.0) {
        bail!(
            ErrorInvalidArgument,
            "PatchexExtrapolateDesc.alpha {} must be in (0, 1]",
            desc.alpha
        );
    }
    let geometry = geometry(
        gpu,
        &desc.geometry,
        "PatchexExtrapolateDesc.geometry",
        extent,
    )?;
    let Some(motion_vectors) = geometry.motion_vectors else {
        bail!(
            ErrorNullPointer,
            "PatchexExtrapolateDesc.geometry.motion_vectors is required to extrapolate"
        );
    };
    Ok(TargetInputs {
        alpha: desc.alpha,
        extent,
        base_color: ImportedImage::import_required(
            gpu,
            &desc.base_color,
            &ImageRole::input("PatchexExtrapolateDesc.base_color", FLOAT_COLOR_FORMATS),
            extent,
        )?,
        material: ImportedImage::import(
            gpu,
            &desc.material,
            &ImageRole::input("PatchexExtrapolateDesc.material", FLOAT_COLOR_FORMATS),
            extent,
        )?,
        motion_vectors,
        geometry,
        output: ImportedImage::import_required(
            gpu,
            &desc.output,
            &ImageRole::output("PatchexExtrapolateDesc.output"),
            extent,
        )?,
    })
}
