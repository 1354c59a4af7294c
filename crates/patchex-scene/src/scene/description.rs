//! The TOML scene format. Asset paths are relative to the assets folder (by default the
//! `assets/` folder next to the scene file's folder). Lengths are metres, angles degrees.

use serde::Deserialize;

use super::glass::GlassDescription;
use super::particles::EmitterDescription;
use super::wall::WallDescription;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDescription {
    pub name: String,
    /// Frame rate of the written stream (twice the rate of the "rendered" frames).
    #[serde(default = "default_fps")]
    pub fps: f32,
    /// Scene time of frame 0 in seconds.
    #[serde(default)]
    pub start_time: f32,
    pub camera: CameraDescription,
    #[serde(default)]
    pub sun: SunDescription,
    pub ground: Option<GroundDescription>,
    #[serde(default)]
    pub environment: Vec<PropDescription>,
    #[serde(default)]
    pub scatter: Vec<ScatterDescription>,
    #[serde(default)]
    pub character: Vec<CharacterDescription>,
    #[serde(default)]
    pub glass: Vec<GlassDescription>,
    #[serde(default)]
    pub wall: Vec<WallDescription>,
    #[serde(default)]
    pub particles: Vec<EmitterDescription>,
}

fn default_fps() -> f32 {
    60.0
}

#[derive(Clone, Debug, Deserialize)]
pub struct CameraDescription {
    #[serde(default = "default_fov")]
    pub fov_deg: f32,
    #[serde(default = "default_near")]
    pub near: f32,
    #[serde(default = "default_far")]
    pub far: f32,
    pub shake: Option<ShakeDescription>,
    #[serde(flatten)]
    pub rig: CameraRig,
}

fn default_fov() -> f32 {
    50.0
}
fn default_near() -> f32 {
    0.1
}
fn default_far() -> f32 {
    300.0
}

#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum CameraRig {
    Static {
        position: [f32; 3],
        target: [f32; 3],
    },
    /// Circles `center` at `radius` and `height` above it, looking at the centre.
    Orbit {
        center: [f32; 3],
        radius: f32,
        height: f32,
        degrees_per_second: f32,
        #[serde(default)]
        start_deg: f32,
    },
    /// Moves along `path` at `speed` m/s (looping), looking at `target`.
    Dolly {
        path: Vec<[f32; 3]>,
        speed: f32,
        target: [f32; 3],
    },
    /// Stands at `position` and turns: yaw `start_deg + degrees_per_second * t` about the
    /// vertical (0 looks along +x, 90 along +z), pitched down by `pitch_deg`.
    Pan {
        position: [f32; 3],
        degrees_per_second: f32,
        #[serde(default)]
        start_deg: f32,
        #[serde(default)]
        pitch_deg: f32,
    },
    /// Keeps `offset` from the named character (in its facing frame), looking at it.
    Follow {
        character: String,
        offset: [f32; 3],
        #[serde(default = "default_look_height")]
        look_height: f32,
    },
}

fn default_look_height() -> f32 {
    1.0
}

/// A little handheld shake: a sum of incommensurate sines, deterministic in time.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShakeDescription {
    pub amplitude: f32,
    pub frequency: f32,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SunDescription {
    pub azimuth_deg: f32,
    pub elevation_deg: f32,
    /// Sun irradiance per RGB channel (linear, arbitrary units).
    pub color: [f32; 3],
    pub intensity: f32,
    pub sky_zenith: [f32; 3],
    pub sky_horizon: [f32; 3],
    pub ground_ambient: [f32; 3],
    pub shadow_resolution: u32,
    /// Centre and half-size of the square the shadow map covers; fitted to the scene if absent.
    pub shadow_center: Option<[f32; 3]>,
    pub shadow_radius: Option<f32>,
}

impl Default for SunDescription {
    fn default() -> Self {
        Self {
            azimuth_deg: 35.0,
            elevation_deg: 45.0,
            color: [1.0, 0.95, 0.88],
            intensity: 3.0,
            sky_zenith: [0.25, 0.4, 0.75],
            sky_horizon: [0.7, 0.8, 0.9],
            ground_ambient: [0.12, 0.11, 0.1],
            shadow_resolution: 2048,
            shadow_center: None,
            shadow_radius: None,
        }
    }
}

/// A flat square at y = `height`, for kits that have no ground of their own.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundDescription {
    pub size: f32,
    #[serde(default)]
    pub height: f32,
    pub base_color: [f32; 3],
    #[serde(default = "default_ground_roughness")]
    pub roughness: f32,
    /// Paves the square with tiles; plain without.
    pub tiles: Option<TilesDescription>,
}

fn default_ground_roughness() -> f32 {
    0.9
}

/// Square tiles with bevelled grooves, each a shade of its own, their faces lightly pitted: fine
/// normal-mapped detail, near and magnified or far and minified, which a glossy finish turns
/// into highlights.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TilesDescription {
    /// Side of one tile, in metres.
    pub size: f32,
    /// How much the tiles' shades differ, 0 to 1.
    #[serde(default = "default_tile_variation")]
    pub variation: f32,
}

fn default_tile_variation() -> f32 {
    0.25
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PropDescription {
    pub asset: String,
    #[serde(default)]
    pub position: [f32; 3],
    #[serde(default)]
    pub yaw_deg: f32,
    #[serde(default = "default_scale")]
    pub scale: f32,
    /// Characters stand on the highest `ground` prop under them; path heights become
    /// offsets above it.
    #[serde(default)]
    pub ground: bool,
}

fn default_scale() -> f32 {
    1.0
}

/// Seeded random placement of props in a ring, for forests and grass.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScatterDescription {
    pub assets: Vec<String>,
    pub count: usize,
    pub center: [f32; 3],
    #[serde(default)]
    pub radius_min: f32,
    pub radius_max: f32,
    #[serde(default = "default_scale")]
    pub scale_min: f32,
    #[serde(default = "default_scale")]
    pub scale_max: f32,
    pub seed: u64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CharacterDescription {
    pub name: String,
    pub asset: String,
    /// Animation clip name; the character holds its rest pose without one.
    pub clip: Option<String>,
    /// Playback speed of the clip.
    #[serde(default = "default_scale")]
    pub clip_speed: f32,
    #[serde(default)]
    pub clip_offset: f32,
    #[serde(default = "default_scale")]
    pub scale: f32,
    /// Added to the walking direction's yaw, for models whose forward axis is not +z.
    #[serde(default)]
    pub yaw_offset_deg: f32,
    /// Waypoints over the ground (heights are offsets above `ground` props where the scene
    /// has them); one point keeps the character in place.
    pub path: Vec<[f32; 3]>,
    /// Walking speed along the path in m/s.
    #[serde(default)]
    pub walk_speed: f32,
    /// Yaw used while standing still (single-point path or zero speed).
    #[serde(default)]
    pub yaw_deg: f32,
}
