//! The dataset's layers, named as Unreal exports them, and where each one sits in the resolve
//! pass's planes buffer (keep in sync with the PLANE_* constants of shaders/resolve.wgsl).

pub struct LayerSpec {
    pub name: &'static str,
    pub channels: &'static [&'static str],
    /// First plane of this layer in the resolve output.
    pub first_plane: usize,
    /// Only present when the frame is lit (absent in G-buffer-only frames).
    pub lit: bool,
}

const RGB: &[&str] = &["R", "G", "B"];
const R: &[&str] = &["R"];

pub const FINAL_IMAGE: &str = "FinalImage";
pub const BASE_COLOR: &str = "BaseColor";
pub const METALLIC: &str = "Metallic";
pub const SPECULAR: &str = "Specular";
pub const ROUGHNESS: &str = "Roughness";
pub const SCENE_DEPTH: &str = "SceneDepth";
pub const WORLD_NORMAL: &str = "WorldNormal";
pub const WORLD_POSITION: &str = "WorldPosition";
pub const CUSTOM_STENCIL: &str = "CustomStencil";
pub const MOTION_VECTOR: &str = "MotionVector";
pub const NOV: &str = "NoV";
pub const SHADOW_MASK: &str = "ShadowMask";
pub const FINAL_IMAGE_NO_DYNAMIC_SHADOWS: &str = "FinalImageNoDynamicShadows";
/// The view-dependent part of FinalImage: the sun's and the sky's specular reflection.
pub const SPECULAR_LIGHT: &str = "SpecularLight";
/// The sun's visibility through static casters; the sun's whole visibility is this times
/// ShadowMask (dynamic casters).
pub const STATIC_SHADOW_MASK: &str = "StaticShadowMask";

/// Coverage of the translucency drawn after lighting (blended surfaces and particles), in
/// [0, 1]: the mask an engine hands a frame generator. Written, with TranslucencyMotion, only by
/// scenes that draw translucency, and not among the resolve pass's planes.
pub const TRANSLUCENCY_MASK: &str = "TranslucencyMask";
/// The translucency's own backward motion in pixels, where TranslucencyMask is above 0.
pub const TRANSLUCENCY_MOTION: &str = "TranslucencyMotion";
/// FinalImage before the translucency is drawn over it: the lit opaque surfaces alone, what an
/// engine's scene colour holds before its translucency pass.
pub const FINAL_IMAGE_OPAQUE: &str = "FinalImageOpaque";
/// FinalImageNoDynamicShadows before the translucency is drawn over it: the shadow input an
/// engine that hands over its scene colour before its translucency pass gives with it.
pub const FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS: &str = "FinalImageOpaqueNoDynamicShadows";
/// The layers a scene that draws translucency adds.
pub const TRANSLUCENCY_LAYERS: [&str; 4] = [
    TRANSLUCENCY_MASK,
    TRANSLUCENCY_MOTION,
    FINAL_IMAGE_OPAQUE,
    FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS,
];

pub const LAYERS: &[LayerSpec] = &[
    LayerSpec {
        name: FINAL_IMAGE,
        channels: RGB,
        first_plane: 0,
        lit: true,
    },
    LayerSpec {
        name: BASE_COLOR,
        channels: RGB,
        first_plane: 3,
        lit: false,
    },
    LayerSpec {
        name: METALLIC,
        channels: R,
        first_plane: 6,
        lit: false,
    },
    LayerSpec {
        name: SPECULAR,
        channels: R,
        first_plane: 7,
        lit: false,
    },
    LayerSpec {
        name: ROUGHNESS,
        channels: R,
        first_plane: 8,
        lit: false,
    },
    LayerSpec {
        name: SCENE_DEPTH,
        channels: R,
        first_plane: 9,
        lit: false,
    },
    LayerSpec {
        name: WORLD_NORMAL,
        channels: RGB,
        first_plane: 10,
        lit: false,
    },
    LayerSpec {
        name: WORLD_POSITION,
        channels: RGB,
        first_plane: 13,
        lit: false,
    },
    LayerSpec {
        name: CUSTOM_STENCIL,
        channels: R,
        first_plane: 16,
        lit: false,
    },
    LayerSpec {
        name: MOTION_VECTOR,
        channels: &["R", "G"],
        first_plane: 17,
        lit: false,
    },
    LayerSpec {
        name: NOV,
        channels: R,
        first_plane: 19,
        lit: false,
    },
    LayerSpec {
        name: SHADOW_MASK,
        channels: R,
        first_plane: 20,
        lit: false,
    },
    LayerSpec {
        name: FINAL_IMAGE_NO_DYNAMIC_SHADOWS,
        channels: RGB,
        first_plane: 21,
        lit: true,
    },
    LayerSpec {
        name: SPECULAR_LIGHT,
        channels: RGB,
        first_plane: 24,
        lit: true,
    },
    LayerSpec {
        name: STATIC_SHADOW_MASK,
        channels: R,
        first_plane: 27,
        lit: false,
    },
];

/// Number of f32 planes the resolve pass writes.
pub const PLANE_COUNT: usize = 28;

pub fn layer_spec(name: &str) -> Option<&'static LayerSpec> {
    LAYERS.iter().find(|layer| layer.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_are_contiguous_and_cover_the_buffer() {
        let mut next = 0;
        for layer in LAYERS {
            assert_eq!(
                layer.first_plane, next,
                "{} does not follow its predecessor",
                layer.name
            );
            next += layer.channels.len();
        }
        assert_eq!(next, PLANE_COUNT);
    }
}
