//! What a context or a call is configured with: the preset, the extension structs chained on
//! a create info or a call (validated by `ffi`), the defaults they override, and the networks'
//! weights.

use std::path::PathBuf;

use crate::abi::*;
use crate::error::{bail, Result};
use crate::network::{self, Network, TensorPrecision};
use crate::passes::segmentation::SegmentationSettings;
use crate::passes::shadow_flow::FlowSettings;
use crate::passes::warp::WarpSettings;

pub const NEEDS_SHADOW_PRESET: &str =
    "needs a context made with PATCHEX_PRESET_WARP_AND_SHADOWS or PATCHEX_PRESET_FULL";

/// Extension structs chained on a create info or an extrapolate call, validated.
#[derive(Default)]
pub struct Extensions {
    pub warp: Option<WarpSettings>,
    pub segmentation: Option<SegmentationSettings>,
    pub diagnostics: Option<PatchexImage>,
    pub shadow_diagnostics: Option<PatchexImage>,
    pub shadow: Option<PatchexShadowInput>,
    /// `PatchexTargetShadowInput.mask`.
    pub target_shadow_mask: Option<PatchexImage>,
    pub flow: Option<FlowSettings>,
    pub sun: Option<PatchexSunLight>,
    pub sky: Option<PatchexSkyLight>,
    pub translucency: Option<PatchexTranslucencyInput>,
    pub network_weights: Option<NetworkWeightPaths>,
    pub networks: Option<NetworkSwitches>,
    pub network_precision: Option<TensorPrecision>,
    /// `PatchexNetworkMemory.max_patch_side`, validated.
    pub network_max_patch_side: Option<u32>,
}

/// Weight files in place of the built-in networks (`PatchexNetworkWeights`).
#[derive(Clone, Debug, Default)]
pub struct NetworkWeightPaths {
    pub fi: Option<PathBuf>,
    pub near_be: Option<PathBuf>,
}

/// Which region's network runs (`PatchexNetworkSettings`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NetworkSwitches {
    pub fi: bool,
    pub near_be: bool,
    /// The FI network over the whole frame instead of the patches (needs `fi`).
    pub whole_frame: bool,
    /// Frame pixels per network texel on each axis: 1, 2 or 4.
    pub divisor: u32,
    /// The paper's blend: corrections over every pixel of their region, not only holes.
    pub correct_valid_pixels: bool,
}

impl Default for NetworkSwitches {
    fn default() -> Self {
        Self {
            fi: true,
            near_be: true,
            whole_frame: false,
            divisor: 1,
            correct_valid_pixels: false,
        }
    }
}

impl NetworkSwitches {
    /// Which of the FI and near-BE networks run: whole-frame runs FI alone.
    pub fn running(&self) -> [bool; 2] {
        [self.fi, self.near_be && !self.whole_frame]
    }
}

/// What a preset runs.
#[derive(Clone, Copy, Debug)]
pub struct Preset {
    /// The two inpainting networks (NETWORKS, FULL).
    pub networks: bool,
    /// The shadow sub-task on frames with a shadow input (WARP_AND_SHADOWS, FULL).
    pub shadows: bool,
}

impl Preset {
    /// The preset `preset` names, checked against the extensions chained on the create info.
    pub fn new(preset: PatchexPreset, defaults: &Extensions) -> Result<Self> {
        let (networks, shadows) = match preset {
            PATCHEX_PRESET_WARP_ONLY => (false, false),
            PATCHEX_PRESET_NETWORKS => (true, false),
            PATCHEX_PRESET_WARP_AND_SHADOWS => (false, true),
            PATCHEX_PRESET_FULL => (true, true),
            other => bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo.preset {other} is not a preset: PATCHEX_PRESET_WARP_ONLY (0), \
                 PATCHEX_PRESET_NETWORKS (1), PATCHEX_PRESET_WARP_AND_SHADOWS (2) or \
                 PATCHEX_PRESET_FULL (3)"
            ),
        };
        if !networks
            && (defaults.network_weights.is_some()
                || defaults.networks.is_some()
                || defaults.network_precision.is_some()
                || defaults.network_max_patch_side.is_some())
        {
            bail!(
                ErrorInvalidArgument,
                "PatchexNetworkWeights, PatchexNetworkSettings, PatchexNetworkPrecision and \
                 PatchexNetworkMemory need PATCHEX_PRESET_NETWORKS or PATCHEX_PRESET_FULL"
            );
        }
        if !shadows && defaults.flow.is_some() {
            bail!(
                ErrorInvalidArgument,
                "PatchexShadowFlowSettings {NEEDS_SHADOW_PRESET}"
            );
        }
        Ok(Self { networks, shadows })
    }
}

/// The settings a call uses where it chains none of its own.
pub struct Defaults {
    pub warp: WarpSettings,
    pub segmentation: SegmentationSettings,
    pub flow: FlowSettings,
    pub networks: NetworkSwitches,
}

impl Defaults {
    pub fn new(extensions: &Extensions) -> Self {
        Self {
            warp: extensions.warp.unwrap_or_default(),
            segmentation: extensions.segmentation.unwrap_or_default(),
            flow: extensions.flow.unwrap_or_default(),
            networks: extensions.networks.unwrap_or_default(),
        }
    }
}

impl NetworkWeightPaths {
    /// The FI and near-BE networks, from these files or the shipped weights. Read before any
    /// Vulkan object is made: a bad file costs nothing to refuse.
    pub fn load(&self) -> Result<[Network; 2]> {
        Ok([
            network::load(self.fi.as_deref(), network::SHIPPED_FI, "FI")?,
            network::load(self.near_be.as_deref(), network::SHIPPED_NEAR_BE, "near-BE")?,
        ])
    }
}
