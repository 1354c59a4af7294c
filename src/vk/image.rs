//! Engine images imported for one call, and images the plugin owns.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::abi::PatchexImage;
use crate::error::{bail, Error, Result};
use crate::vk::device::Gpu;

/// What one input or output of a call accepts.
pub struct ImageRole<'a> {
    /// The argument's name as the engine sees it, for error messages.
    pub name: &'a str,
    pub formats: &'static [vk::Format],
    /// Usage the image must have been created with.
    pub usage: vk::ImageUsageFlags,
    /// Format feature the device must support for this use.
    pub feature: vk::FormatFeatureFlags,
    /// Formats the plugin fills by copying packed texels from a working image into the
    /// engine's (outputs whose format a shader cannot store): they need TRANSFER_DST usage
    /// instead, and no format feature, since the engine could create the image with it.
    pub copied_formats: &'static [vk::Format],
}

/// Colour formats readable as `texture_2d<f32>`.
pub const FLOAT_COLOR_FORMATS: &[vk::Format] = &[
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32G32B32A32_SFLOAT,
    vk::Format::B10G11R11_UFLOAT_PACK32,
    vk::Format::A2B10G10R10_UNORM_PACK32,
    vk::Format::A2R10G10B10_UNORM_PACK32,
    vk::Format::R8G8B8A8_UNORM,
    vk::Format::R8G8B8A8_SRGB,
    vk::Format::B8G8R8A8_UNORM,
    vk::Format::B8G8R8A8_SRGB,
    vk::Format::R8G8B8A8_SNORM,
    vk::Format::R16G16B16A16_UNORM,
    vk::Format::R16G16B16A16_SNORM,
];
pub const MOTION_FORMATS: &[vk::Format] = &[
    vk::Format::R16G16_SFLOAT,
    vk::Format::R32G32_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32G32B32A32_SFLOAT,
];
pub const DEPTH_FORMATS: &[vk::Format] = &[
    vk::Format::R32_SFLOAT,
    vk::Format::R16_SFLOAT,
    vk::Format::D32_SFLOAT,
    vk::Format::D16_UNORM,
    vk::Format::D24_UNORM_S8_UINT,
    vk::Format::D32_SFLOAT_S8_UINT,
];
/// 8-bit object ids; wider ids would not survive the plugin's f16 packing exactly.
pub const STENCIL_FORMATS: &[vk::Format] = &[
    vk::Format::R8_UINT,
    vk::Format::S8_UINT,
    vk::Format::D16_UNORM_S8_UINT,
    vk::Format::D24_UNORM_S8_UINT,
    vk::Format::D32_SFLOAT_S8_UINT,
];
/// The shadow mask: its first channel is read. Single-channel float and UNORM formats, or any
/// float colour format.
pub const MASK_FORMATS: &[vk::Format] = &[
    vk::Format::R8_UNORM,
    vk::Format::R16_UNORM,
    vk::Format::R16_SFLOAT,
    vk::Format::R32_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32G32B32A32_SFLOAT,
    vk::Format::R8G8B8A8_UNORM,
];
/// The output: RGBA16F is written by the last pass itself; the 32-bit formats engines keep scene
/// colour in or present from are packed by a pass (`passes::pack_output`) and copied in: UNORM
/// clamps to [0, 1], SRGB encodes, B10G11R11 drops alpha and clamps negatives to 0.
pub const OUTPUT_FORMATS: &[vk::Format] = &[
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::B10G11R11_UFLOAT_PACK32,
    vk::Format::A2B10G10R10_UNORM_PACK32,
    vk::Format::R8G8B8A8_UNORM,
    vk::Format::R8G8B8A8_SRGB,
    vk::Format::B8G8R8A8_UNORM,
    vk::Format::B8G8R8A8_SRGB,
];
/// The output formats packed and copied (every output format but RGBA16F).
pub const PACKED_OUTPUT_FORMATS: &[vk::Format] = OUTPUT_FORMATS.split_at(1).1;
/// Diagnostics images, written by their passes directly.
pub const DIAGNOSTICS_FORMATS: &[vk::Format] = &[vk::Format::R16G16B16A16_SFLOAT];

impl<'a> ImageRole<'a> {
    pub const fn input(name: &'a str, formats: &'static [vk::Format]) -> Self {
        Self {
            name,
            formats,
            usage: vk::ImageUsageFlags::SAMPLED,
            feature: vk::FormatFeatureFlags::SAMPLED_IMAGE,
            copied_formats: &[],
        }
    }

    /// The extrapolated frame.
    pub const fn output(name: &'a str) -> Self {
        Self {
            name,
            formats: OUTPUT_FORMATS,
            usage: vk::ImageUsageFlags::STORAGE,
            feature: vk::FormatFeatureFlags::STORAGE_IMAGE,
            copied_formats: PACKED_OUTPUT_FORMATS,
        }
    }

    /// A diagnostics image, written by a pass.
    pub const fn diagnostics(name: &'a str) -> Self {
        Self {
            formats: DIAGNOSTICS_FORMATS,
            copied_formats: &[],
            ..Self::output(name)
        }
    }

    /// The usage and format feature an image of `format` needs in this role.
    fn needs(&self, format: vk::Format) -> (vk::ImageUsageFlags, vk::FormatFeatureFlags) {
        if self.copied_formats.contains(&format) {
            (
                vk::ImageUsageFlags::TRANSFER_DST,
                vk::FormatFeatureFlags::empty(),
            )
        } else {
            (self.usage, self.feature)
        }
    }
}

/// An engine image checked for one use. It is only borrowed for the call being recorded.
#[derive(Clone, Copy, Debug)]
pub struct ImportedImage {
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub layout: vk::ImageLayout,
    /// An output the plugin fills by a copy from a working image (`ImageRole::copied_formats`).
    pub written_by_copy: bool,
    /// What the passes read or write of it: the frame's extent, in the aspect its view shows.
    pub bytes: u64,
    /// Mips its view shows, from mip 0, which barriers cover.
    pub mip_levels: u32,
}

impl ImportedImage {
    /// Checks an engine image against `role` and the frame extent. `Ok(None)` when the engine
    /// passed no image, which the caller accepts only for optional inputs.
    pub fn import(
        gpu: &Gpu,
        desc: &PatchexImage,
        role: &ImageRole,
        extent: vk::Extent2D,
    ) -> Result<Option<Self>> {
        let name = role.name;
        if desc.image == vk::Image::null() {
            return Ok(None);
        }
        if desc.view == vk::ImageView::null() {
            bail!(
                ErrorNullPointer,
                "{name}: image is set but view is VK_NULL_HANDLE"
            );
        }
        if !role.formats.contains(&desc.format) {
            bail!(
                ErrorUnsupportedFormat,
                "{name}: format {:?} is not accepted; use one of {:?}",
                desc.format,
                role.formats
            );
        }
        let (usage, feature) = role.needs(desc.format);
        if !gpu.format_features(desc.format).contains(feature) {
            bail!(
                ErrorUnsupportedFormat,
                "{name}: the device does not support {feature:?} for format {:?}",
                desc.format
            );
        }
        if !desc.usage.contains(usage) {
            bail!(
                ErrorMissingImageUsage,
                "{name}: usage {:?} lacks {usage:?}, which a {:?} image needs here",
                desc.usage,
                desc.format
            );
        }
        if !is_supported_layout(desc.layout) {
            bail!(
                ErrorInvalidLayout,
                "{name}: layout {:?} is not one the plugin can transition from and back to",
                desc.layout
            );
        }
        if let Err(reason) = layout_fits_image(desc.layout, aspects_of(desc.format), desc.usage) {
            bail!(
                ErrorInvalidLayout,
                "{name}: layout {:?} cannot hold a {:?} image with usage {:?}: {reason}",
                desc.layout,
                desc.format,
                desc.usage
            );
        }
        if desc.width < extent.width || desc.height < extent.height {
            bail!(
                ErrorMismatchedExtent,
                "{name}: image is {}x{}, smaller than the frame's {}x{}",
                desc.width,
                desc.height,
                extent.width,
                extent.height
            );
        }
        // A depth-stencil image is viewed through one aspect: the stencil's for the stencil role.
        let aspect = if role.formats == STENCIL_FORMATS {
            vk::ImageAspectFlags::STENCIL
        } else {
            vk::ImageAspectFlags::COLOR | vk::ImageAspectFlags::DEPTH
        };
        Ok(Some(Self {
            image: desc.image,
            view: desc.view,
            format: desc.format,
            layout: desc.layout,
            written_by_copy: role.copied_formats.contains(&desc.format),
            bytes: texel_bytes(desc.format, aspect) * pixels(extent),
            mip_levels: 1,
        }))
    }

    /// Like `import`, for inputs the call cannot do without.
    pub fn import_required(
        gpu: &Gpu,
        desc: &PatchexImage,
        role: &ImageRole,
        extent: vk::Extent2D,
    ) -> Result<Self> {
        match Self::import(gpu, desc, role, extent)? {
            Some(image) => Ok(image),
            None => bail!(
                ErrorNullPointer,
                "{}: image is VK_NULL_HANDLE but required",
                role.name
            ),
        }
    }

    /// Aspects a barrier on this image must name (both for combined depth/stencil formats).
    pub fn barrier_aspects(&self) -> vk::ImageAspectFlags {
        aspects_of(self.format)
    }
}

/// Every aspect of an image of `format`.
fn aspects_of(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D16_UNORM | vk::Format::D32_SFLOAT => vk::ImageAspectFlags::DEPTH,
        vk::Format::S8_UINT => vk::ImageAspectFlags::STENCIL,
        vk::Format::D16_UNORM_S8_UINT
        | vk::Format::D24_UNORM_S8_UINT
        | vk::Format::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::COLOR,
    }
}

/// Whether an image with `aspects` and `usage` can be in `layout`, as the barrier that moves it
/// out requires (VkImageMemoryBarrier's oldLayout rules); otherwise why not.
fn layout_fits_image(
    layout: vk::ImageLayout,
    aspects: vk::ImageAspectFlags,
    usage: vk::ImageUsageFlags,
) -> std::result::Result<(), &'static str> {
    use vk::ImageAspectFlags as A;
    use vk::ImageLayout as L;
    use vk::ImageUsageFlags as U;
    let color = aspects == A::COLOR;
    let (depth, stencil) = (aspects.contains(A::DEPTH), aspects.contains(A::STENCIL));
    let needs = |wanted: U, what| {
        if usage.intersects(wanted) {
            Ok(())
        } else {
            Err(what)
        }
    };
    let colour_only = |what| if color { Ok(()) } else { Err(what) };
    let depth_stencil = |what| if color { Err(what) } else { Ok(()) };
    const DS_ATTACHMENT: &str = "a depth/stencil layout needs a depth/stencil format and \
                                 DEPTH_STENCIL_ATTACHMENT usage";
    match layout {
        L::GENERAL => Ok(()),
        L::COLOR_ATTACHMENT_OPTIMAL | L::PRESENT_SRC_KHR => {
            colour_only("a colour layout needs a colour format")?;
            if layout == L::COLOR_ATTACHMENT_OPTIMAL {
                needs(U::COLOR_ATTACHMENT, "it needs COLOR_ATTACHMENT usage")?;
            }
            Ok(())
        }
        L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
        | L::DEPTH_STENCIL_READ_ONLY_OPTIMAL
        | L::DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL
        | L::DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL => {
            depth_stencil(DS_ATTACHMENT)?;
            needs(U::DEPTH_STENCIL_ATTACHMENT, DS_ATTACHMENT)
        }
        // The separate layouts name one aspect; the plugin's barrier names every aspect of the
        // image, so they fit only formats that have just that aspect.
        L::DEPTH_ATTACHMENT_OPTIMAL | L::DEPTH_READ_ONLY_OPTIMAL => {
            if !depth || stencil {
                return Err(
                    "a depth-only layout needs a depth-only format (D16_UNORM, D32_SFLOAT)",
                );
            }
            needs(U::DEPTH_STENCIL_ATTACHMENT, DS_ATTACHMENT)
        }
        L::STENCIL_ATTACHMENT_OPTIMAL | L::STENCIL_READ_ONLY_OPTIMAL => {
            if !stencil || depth {
                return Err("a stencil-only layout needs a stencil-only format (S8_UINT)");
            }
            needs(U::DEPTH_STENCIL_ATTACHMENT, DS_ATTACHMENT)
        }
        L::SHADER_READ_ONLY_OPTIMAL => needs(
            U::SAMPLED | U::INPUT_ATTACHMENT,
            "it needs SAMPLED or INPUT_ATTACHMENT usage",
        ),
        L::TRANSFER_SRC_OPTIMAL => needs(U::TRANSFER_SRC, "it needs TRANSFER_SRC usage"),
        L::TRANSFER_DST_OPTIMAL => needs(U::TRANSFER_DST, "it needs TRANSFER_DST usage"),
        L::ATTACHMENT_OPTIMAL => {
            let attachment = if color {
                U::COLOR_ATTACHMENT
            } else {
                U::DEPTH_STENCIL_ATTACHMENT
            };
            needs(
                attachment,
                "it needs the attachment usage of the image's aspect",
            )
        }
        L::READ_ONLY_OPTIMAL => needs(
            U::SAMPLED | U::INPUT_ATTACHMENT | U::DEPTH_STENCIL_ATTACHMENT,
            "it needs SAMPLED, INPUT_ATTACHMENT or DEPTH_STENCIL_ATTACHMENT usage",
        ),
        _ => Err("the plugin does not take images in it"),
    }
}

/// Layouts an engine image may be handed in: every core layout that holds defined contents.
fn is_supported_layout(layout: vk::ImageLayout) -> bool {
    matches!(
        layout,
        vk::ImageLayout::GENERAL
            | vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
            | vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
            | vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
            | vk::ImageLayout::TRANSFER_SRC_OPTIMAL
            | vk::ImageLayout::TRANSFER_DST_OPTIMAL
            | vk::ImageLayout::DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL
            | vk::ImageLayout::DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL
            | vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL
            | vk::ImageLayout::STENCIL_ATTACHMENT_OPTIMAL
            | vk::ImageLayout::STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::READ_ONLY_OPTIMAL
            | vk::ImageLayout::ATTACHMENT_OPTIMAL
            | vk::ImageLayout::PRESENT_SRC_KHR
    )
}

/// A 2D image the plugin allocated. It lives in GENERAL layout from its first use on, read as a
/// texture and (with STORAGE usage) written as a storage image.
pub struct OwnedImage {
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub layers: u32,
    allocation: Option<Allocation>,
    /// Whether a command buffer has already moved it out of UNDEFINED.
    pub initialized: bool,
}

impl OwnedImage {
    pub fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        name: &str,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        Self::with_layers(gpu, allocator, name, format, extent, usage, None)
    }

    /// An image of `layers` layers, viewed as a 2D array (`texture_2d_array` in shaders).
    pub fn array(
        gpu: &Gpu,
        allocator: &mut Allocator,
        name: &str,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
        layers: u32,
    ) -> Result<Self> {
        Self::with_layers(gpu, allocator, name, format, extent, usage, Some(layers))
    }

    fn with_layers(
        gpu: &Gpu,
        allocator: &mut Allocator,
        name: &str,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
        array_layers: Option<u32>,
    ) -> Result<Self> {
        let device = &gpu.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(array_layers.unwrap_or(1))
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let during = |error: Error| {
            error.during(format_args!(
                "creating the {name} image ({}x{} {format:?})",
                extent.width, extent.height
            ))
        };
        // SAFETY: valid device and create info; every handle made here is destroyed on error.
        unsafe {
            let image = device
                .create_image(&info, None)
                .map_err(|e| during(e.into()))?;
            let requirements = device.get_image_memory_requirements(image);
            let allocation = match allocator.allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            }) {
                Ok(allocation) => allocation,
                Err(error) => {
                    device.destroy_image(image, None);
                    return Err(during(error.into()));
                }
            };
            let mut owned = Self {
                image,
                view: vk::ImageView::null(),
                format,
                extent,
                layers: array_layers.unwrap_or(1),
                allocation: Some(allocation),
                initialized: false,
            };
            let bound = device.bind_image_memory(
                image,
                owned.allocation.as_ref().unwrap().memory(),
                owned.allocation.as_ref().unwrap().offset(),
            );
            let view = bound.and_then(|()| {
                device.create_image_view(
                    &vk::ImageViewCreateInfo::default()
                        .image(image)
                        .view_type(match array_layers {
                            Some(_) => vk::ImageViewType::TYPE_2D_ARRAY,
                            None => vk::ImageViewType::TYPE_2D,
                        })
                        .format(format)
                        .subresource_range(ALL_LAYERS),
                    None,
                )
            });
            match view {
                Ok(view) => owned.view = view,
                Err(error) => {
                    owned.destroy(gpu, allocator);
                    return Err(during(error.into()));
                }
            }
            Ok(owned)
        }
    }

    /// An image that holds nothing; destroying it is a no-op.
    pub fn null() -> Self {
        Self {
            image: vk::Image::null(),
            view: vk::ImageView::null(),
            format: vk::Format::UNDEFINED,
            extent: vk::Extent2D::default(),
            layers: 0,
            allocation: None,
            initialized: true,
        }
    }

    pub fn size_bytes(&self) -> u64 {
        self.allocation.as_ref().map_or(0, |a| a.size())
    }

    /// The bytes of its texels, every layer: what a pass that reads or writes it all moves.
    pub fn texel_bytes(&self) -> u64 {
        texel_bytes(self.format, vk::ImageAspectFlags::COLOR)
            * pixels(self.extent)
            * self.layers as u64
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        // SAFETY: the caller guarantees the GPU no longer uses the image (deferred destruction).
        unsafe {
            gpu.device.destroy_image_view(self.view, None);
            gpu.device.destroy_image(self.image, None);
        }
        if let Some(allocation) = self.allocation.take() {
            // Freeing a live allocation only fails on allocator bugs; nothing to recover.
            let _ = allocator.free(allocation);
        }
    }
}

/// An image a pass samples: its view and the layout it is in while the pass runs.
#[derive(Clone, Copy, Debug)]
pub struct Texture {
    /// The image, by which passes are ordered.
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub layout: vk::ImageLayout,
    /// What a pass that reads or writes all of it moves (`OwnedImage::texel_bytes`,
    /// `ImportedImage::bytes`).
    pub bytes: u64,
}

impl From<&OwnedImage> for Texture {
    fn from(image: &OwnedImage) -> Self {
        Self {
            image: image.image,
            view: image.view,
            layout: vk::ImageLayout::GENERAL,
            bytes: image.texel_bytes(),
        }
    }
}

/// Texels in an image of `extent`.
pub fn pixels(extent: vk::Extent2D) -> u64 {
    extent.width as u64 * extent.height as u64
}

/// Bytes of one texel of `format` as a view of `aspect` shows it (a depth-stencil format's
/// depth or stencil; depth stored in 24 bits takes 4). 0 for a format no list here names, which
/// a test rules out.
pub fn texel_bytes(format: vk::Format, aspect: vk::ImageAspectFlags) -> u64 {
    use vk::Format as F;
    let stencil = aspect == vk::ImageAspectFlags::STENCIL;
    match format {
        F::D16_UNORM_S8_UINT | F::D24_UNORM_S8_UINT | F::D32_SFLOAT_S8_UINT if stencil => 1,
        F::R8_UINT | F::S8_UINT | F::R8_UNORM => 1,
        F::R16_SFLOAT | F::R16_UNORM | F::R16_UINT | F::D16_UNORM | F::D16_UNORM_S8_UINT => 2,
        F::R32_SFLOAT
        | F::R32_UINT
        | F::D32_SFLOAT
        | F::D24_UNORM_S8_UINT
        | F::D32_SFLOAT_S8_UINT
        | F::R16G16_SFLOAT
        | F::B10G11R11_UFLOAT_PACK32
        | F::A2B10G10R10_UNORM_PACK32
        | F::A2R10G10B10_UNORM_PACK32
        | F::R8G8B8A8_UNORM
        | F::R8G8B8A8_SRGB
        | F::B8G8R8A8_UNORM
        | F::B8G8R8A8_SRGB
        | F::R8G8B8A8_SNORM => 4,
        F::R16G16B16A16_SFLOAT
        | F::R16G16B16A16_UNORM
        | F::R16G16B16A16_SNORM
        | F::R32G32_SFLOAT
        | F::R32G32_UINT => 8,
        F::R32G32B32A32_SFLOAT => 16,
        _ => 0,
    }
}

/// Every layer of a plugin image.
pub const ALL_LAYERS: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    layer_count: vk::REMAINING_ARRAY_LAYERS,
    ..COLOR_SUBRESOURCE
};

pub const COLOR_SUBRESOURCE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_accepted_format_has_a_texel_size() {
        let lists = [
            FLOAT_COLOR_FORMATS,
            MOTION_FORMATS,
            DEPTH_FORMATS,
            STENCIL_FORMATS,
            MASK_FORMATS,
            OUTPUT_FORMATS,
            DIAGNOSTICS_FORMATS,
        ];
        for format in lists.into_iter().flatten() {
            assert!(
                texel_bytes(*format, vk::ImageAspectFlags::COLOR) > 0,
                "{format:?}"
            );
        }
        for format in STENCIL_FORMATS {
            assert_eq!(texel_bytes(*format, vk::ImageAspectFlags::STENCIL), 1);
        }
        assert_eq!(
            texel_bytes(vk::Format::D32_SFLOAT_S8_UINT, vk::ImageAspectFlags::DEPTH),
            4
        );
    }
}
