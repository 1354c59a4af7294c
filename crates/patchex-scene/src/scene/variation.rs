//! Seeded scene variation: a set of scene files drawn from one seed, each a family's setting
//! (street, forest, autumn wood, desert, the Littlest Tokyo diorama, and Kenney's city block,
//! race track, platforms and arena) with its characters, clips, paths, camera, sun and start
//! time varied. Families belong to one split each and the
//! validation and test families use assets, characters and camera kinds that training does not,
//! so that what is tuned or trained on one split is measured on content it has not seen.
//! The output is plain scene files: what was generated can be read, rendered and diffed.

use super::placement::SplitMix64;
use std::f32::consts::PI;
use std::fmt::Write;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    Training,
    Validation,
    Test,
}

impl Split {
    pub fn name(self) -> &'static str {
        match self {
            Split::Training => "training",
            Split::Validation => "validation",
            Split::Test => "test",
        }
    }
}

pub struct GeneratedScene {
    pub name: String,
    pub split: Split,
    /// The scene file's text.
    pub text: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CameraKind {
    Orbit,
    /// A dolly sideways past the action, looking at it.
    Strafe,
    Static,
    Follow,
    /// A slow dolly with handheld shake.
    Handheld,
    /// A fast turn on the spot.
    Pan,
}

struct CharacterKind {
    asset: &'static str,
    scale: f32,
    yaw_offset_deg: f32,
    /// The clip it moves with (none for a rigid mover: a vehicle, a drone) and its speed.
    walk: (Option<&'static str>, f32),
    run: Option<(&'static str, f32)>,
    /// A clip played standing in place.
    in_place: Option<&'static str>,
    /// How it moves: on foot anywhere, or as a vehicle or a drone.
    travel: Travel,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Travel {
    /// Across the action area on any heading.
    Walks,
    /// Along the x axis, either way: the race track's.
    Drives,
    /// On any heading, 1.5 to 3 m above the ground, never standing still.
    Flies,
}

const ROBOT: CharacterKind = CharacterKind {
    asset: "characters/RobotExpressive.glb",
    scale: 0.4,
    yaw_offset_deg: 0.0,
    walk: (Some("Walking"), 1.1),
    run: Some(("Running", 4.0)),
    in_place: Some("Dance"),
    travel: Travel::Walks,
};
const CESIUM_MAN: CharacterKind = CharacterKind {
    asset: "characters/CesiumMan.glb",
    scale: 1.0,
    yaw_offset_deg: 90.0,
    walk: (Some("animation0"), 1.2),
    run: None,
    in_place: None,
    travel: Travel::Walks,
};
const CYBERPUNK: CharacterKind = CharacterKind {
    asset: "characters/cyberpunk_Character.glb",
    scale: 1.25,
    yaw_offset_deg: 0.0,
    walk: (Some("CharacterArmature|Walk"), 1.4),
    run: Some(("CharacterArmature|Run", 4.0)),
    in_place: Some("CharacterArmature|Wave"),
    travel: Travel::Walks,
};
const PLATFORMER: CharacterKind = CharacterKind {
    asset: "characters/platformer_Character.glb",
    scale: 0.5,
    yaw_offset_deg: 0.0,
    walk: (Some("CharacterArmature|Walk"), 1.2),
    run: Some(("CharacterArmature|Run", 4.0)),
    in_place: Some("CharacterArmature|Wave"),
    travel: Travel::Walks,
};
const FOX: CharacterKind = CharacterKind {
    asset: "characters/Fox.glb",
    scale: 0.012,
    yaw_offset_deg: 0.0,
    walk: (Some("Walk"), 1.0),
    run: Some(("Run", 5.0)),
    in_place: Some("Survey"),
    travel: Travel::Walks,
};
/// Kenney's platformer character: rigid parts animated by their nodes, no skin.
const KENNEY_CHARACTER: CharacterKind = CharacterKind {
    asset: "kenney/platformer/character.glb",
    scale: 0.9,
    yaw_offset_deg: 0.0,
    walk: (Some("walk"), 1.6),
    run: None,
    in_place: Some("idle"),
    travel: Travel::Walks,
};
const fn vehicle(asset: &'static str, speed: f32) -> CharacterKind {
    CharacterKind {
        asset,
        scale: 1.2,
        yaw_offset_deg: 0.0,
        walk: (None, speed),
        run: None,
        in_place: None,
        travel: Travel::Drives,
    }
}
const TRUCK_RED: CharacterKind = vehicle("kenney/racing/vehicle-truck-red.glb", 9.0);
const TRUCK_GREEN: CharacterKind = vehicle("kenney/racing/vehicle-truck-green.glb", 7.0);
const MOTORCYCLE: CharacterKind = vehicle("kenney/racing/vehicle-motorcycle.glb", 12.0);
const DRONE: CharacterKind = CharacterKind {
    asset: "kenney/fps/enemy-flying.glb",
    scale: 1.0,
    yaw_offset_deg: 0.0,
    walk: (None, 3.0),
    run: None,
    in_place: None,
    travel: Travel::Flies,
};

struct Family {
    name: &'static str,
    split: Split,
    count: usize,
    cameras: &'static [CameraKind],
    characters: &'static [CharacterKind],
    /// Writes the ground, the environment and the scatters, given the bearing of the camera
    /// from the action (radians about +y from +x) and whether the ground is wet.
    setting: fn(&mut SplitMix64, &mut String, f32, bool),
}

const FAMILIES: [Family; 9] = [
    Family {
        name: "street",
        split: Split::Training,
        count: 6,
        cameras: &[
            CameraKind::Orbit,
            CameraKind::Strafe,
            CameraKind::Static,
            CameraKind::Follow,
        ],
        characters: &[ROBOT, CESIUM_MAN, CYBERPUNK],
        setting: street,
    },
    Family {
        name: "forest",
        split: Split::Training,
        count: 6,
        cameras: &[
            CameraKind::Strafe,
            CameraKind::Follow,
            CameraKind::Orbit,
            CameraKind::Static,
        ],
        characters: &[ROBOT, CESIUM_MAN, CYBERPUNK],
        setting: forest,
    },
    Family {
        name: "autumn",
        split: Split::Validation,
        count: 6,
        cameras: &[
            CameraKind::Handheld,
            CameraKind::Pan,
            CameraKind::Follow,
            CameraKind::Orbit,
        ],
        characters: &[PLATFORMER, FOX],
        setting: autumn,
    },
    Family {
        name: "tokyo",
        split: Split::Test,
        count: 3,
        cameras: &[CameraKind::Pan, CameraKind::Handheld, CameraKind::Strafe],
        characters: &[PLATFORMER, FOX],
        setting: tokyo,
    },
    Family {
        name: "desert",
        split: Split::Test,
        count: 3,
        cameras: &[CameraKind::Follow, CameraKind::Pan, CameraKind::Handheld],
        characters: &[PLATFORMER, FOX],
        setting: desert,
    },
    Family {
        name: "city",
        split: Split::Training,
        count: 5,
        cameras: &[
            CameraKind::Static,
            CameraKind::Orbit,
            CameraKind::Follow,
            CameraKind::Strafe,
        ],
        characters: &[ROBOT, CESIUM_MAN, CYBERPUNK],
        setting: city,
    },
    Family {
        name: "racing",
        split: Split::Training,
        count: 5,
        cameras: &[
            CameraKind::Strafe,
            CameraKind::Static,
            CameraKind::Orbit,
            CameraKind::Follow,
        ],
        characters: &[TRUCK_RED, TRUCK_GREEN, MOTORCYCLE, CYBERPUNK],
        setting: racing,
    },
    Family {
        name: "platforms",
        split: Split::Validation,
        count: 4,
        cameras: &[
            CameraKind::Handheld,
            CameraKind::Orbit,
            CameraKind::Pan,
            CameraKind::Follow,
        ],
        characters: &[KENNEY_CHARACTER, FOX],
        setting: platforms,
    },
    Family {
        name: "arena",
        split: Split::Test,
        count: 3,
        cameras: &[CameraKind::Pan, CameraKind::Follow, CameraKind::Handheld],
        characters: &[PLATFORMER, DRONE],
        setting: arena,
    },
];

/// The scenes of each family after its `count` hold translucency: every split has some to be
/// scored on, and the scenes before them stay as they were.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Translucency {
    /// Smoke, sparks or embers, and free-standing panes of glass around the action.
    WithPanes,
    /// Smoke, sparks or embers over wet (glossier) ground, and walls behind the action with
    /// windows glazed onto them: glass that moves with the surface it lies on, a few pixels
    /// across.
    WithWindows,
    /// Smoke, sparks or embers rising between the camera and the action: the layer lies over
    /// the characters, where in the other two it mostly lies beside or behind them.
    BeforeTheAction,
}

const TRANSLUCENCY_SCENES: [Translucency; 3] = [
    Translucency::WithPanes,
    Translucency::WithWindows,
    Translucency::BeforeTheAction,
];

/// The whole set for `seed`: the same seed always gives the same files.
pub fn generate_set(seed: u64) -> Vec<GeneratedScene> {
    let mut scenes = Vec::new();
    for (f, family) in FAMILIES.iter().enumerate() {
        for i in 0..family.count + TRANSLUCENCY_SCENES.len() {
            let mut rng = SplitMix64(seed ^ ((f as u64) << 32 | i as u64).wrapping_mul(0x9E37));
            // Which of the translucency scenes this is, if it is one.
            let nth_translucent = i.checked_sub(family.count);
            let translucency = nth_translucent.map(|t| TRANSLUCENCY_SCENES[t]);
            let camera = match nth_translucent {
                // A camera on the action, where the emitters are.
                Some(t) => {
                    let on_the_action: Vec<CameraKind> = family
                        .cameras
                        .iter()
                        .copied()
                        .filter(|kind| !matches!(kind, CameraKind::Follow | CameraKind::Pan))
                        .collect();
                    on_the_action[t % on_the_action.len()]
                }
                None => family.cameras[i % family.cameras.len()],
            };
            let wet = translucency == Some(Translucency::WithWindows);
            let name = format!("{}_{:02}", family.name, i + 1);
            let (mut text, camera_bearing) = scene_text(&mut rng, &name, family, camera, seed, wet);
            match translucency {
                None => {}
                Some(Translucency::WithPanes) => {
                    particles(&mut rng, &mut text, None);
                    glass(&mut rng, &mut text);
                }
                Some(Translucency::WithWindows) => {
                    particles(&mut rng, &mut text, None);
                    walls(&mut rng, &mut text, camera_bearing);
                }
                Some(Translucency::BeforeTheAction) => {
                    particles(&mut rng, &mut text, Some(camera_bearing));
                }
            }
            scenes.push(GeneratedScene {
                text,
                name,
                split: family.split,
            });
        }
    }
    scenes
}

/// A smoke column in a gusty wind, and sparks or embers, among the characters around the action,
/// or, given the camera's bearing, between the camera and the action.
fn particles(rng: &mut SplitMix64, text: &mut String, towards_camera: Option<f32>) {
    let near = |rng: &mut SplitMix64| {
        let (angle, distance) = match towards_camera {
            Some(bearing) => (bearing + range(rng, -0.4, 0.4), range(rng, 1.5, 3.0)),
            None => (range(rng, 0.0, std::f32::consts::TAU), range(rng, 0.3, 2.0)),
        };
        [distance * angle.cos(), 0.1, distance * angle.sin()]
    };
    let wind = [
        sign(rng) * range(rng, 0.8, 2.0),
        0.15,
        range(rng, -1.0, 1.0),
    ];
    let grey = range(rng, 0.12, 0.5);
    *text += &format!(
        "\n[[particles]]\norigin = {}\norigin_spread = 0.3\nrate = {:.1}\nlifetime = {:.2}\n\
         velocity = [0.0, {:.2}, 0.0]\nvelocity_spread = 0.25\nacceleration = {}\n\
         radius = [0.25, {:.2}]\ncolor = {}\nopacity = {:.2}\nseed = {}\n",
        point(near(rng)),
        range(rng, 10.0, 18.0),
        range(rng, 2.0, 3.0),
        range(rng, 0.6, 1.2),
        point(wind),
        range(rng, 0.7, 1.1),
        point([grey, grey, grey * 1.05]),
        range(rng, 0.4, 0.7),
        rng.next_u64() % 1_000_000,
    );
    // Sparks fly up and fall; embers drift with the smoke.
    let (velocity, spread, acceleration, color) = if rng.next_u64() & 1 == 0 {
        (2.5, 0.8, [0.0, -2.0, 0.0], [6.0, 2.5, 0.6])
    } else {
        (0.8, 0.3, wind, [3.0, 0.9, 0.2])
    };
    *text += &format!(
        "\n[[particles]]\norigin = {}\norigin_spread = 0.2\nrate = {:.1}\nlifetime = 1.20\n\
         velocity = [0.0, {velocity:.2}, 0.0]\nvelocity_spread = {spread:.2}\nacceleration = {}\n\
         radius = [0.05, 0.02]\ncolor = {}\nopacity = 1.0\nseed = {}\n",
        point(near(rng)),
        range(rng, 20.0, 40.0),
        point(acceleration),
        point(color),
        rng.next_u64() % 1_000_000,
    );
}

/// Three panes of tinted glass around the action, each facing it: the camera looks through some
/// of them, and at others behind the characters. They reach below the ground so that uneven
/// ground does not show their bottom edge.
fn glass(rng: &mut SplitMix64, text: &mut String) {
    for _ in 0..3 {
        let angle = range(rng, 0.0, std::f32::consts::TAU);
        let distance = range(rng, 2.2, 3.5);
        let tint = [
            range(rng, 0.55, 0.8),
            range(rng, 0.7, 0.9),
            range(rng, 0.75, 0.95),
        ];
        *text += &format!(
            "\n[[glass]]\nposition = {}\nsize = [{:.2}, {:.2}]\nyaw_deg = {:.1}\ncolor = {}\n\
             opacity = {:.2}\nroughness = {:.2}\n",
            point([distance * angle.cos(), -0.5, distance * angle.sin()]),
            range(rng, 1.5, 3.0),
            range(rng, 2.5, 3.2),
            // Facing the action: the pane's +z towards the origin.
            (-angle.cos()).atan2(-angle.sin()).to_degrees(),
            point(tint),
            range(rng, 0.2, 0.45),
            range(rng, 0.03, 0.15),
        );
    }
}

/// Two or three walls behind the action as the camera sees it, 6 to 9 m out and facing it, each
/// with a grid of windows from slits a few centimetres wide to panes half a metre across.
fn walls(rng: &mut SplitMix64, text: &mut String, camera_bearing: f32) {
    let count = 2 + rng.next_u64() % 2;
    for _ in 0..count {
        let angle = camera_bearing + std::f32::consts::PI + range(rng, -0.9, 0.9);
        let distance = range(rng, 6.0, 9.0);
        let (width, height) = (range(rng, 3.0, 6.0), range(rng, 2.5, 4.0));
        let (columns, rows) = (3 + rng.next_u64() % 4, 2 + rng.next_u64() % 2);
        let window = [
            range(rng, 0.04, 0.5).min(0.8 * width / columns as f32),
            range(rng, 0.3, 1.0).min(0.8 * height / rows as f32),
        ];
        let shade = range(rng, 0.35, 0.75);
        let tint = [
            range(rng, 0.55, 0.8),
            range(rng, 0.7, 0.9),
            range(rng, 0.75, 0.95),
        ];
        *text += &format!(
            "\n[[wall]]\nposition = {}\nsize = [{width:.2}, {height:.2}]\nyaw_deg = {:.1}\n\
             color = {}\nroughness = {:.2}\nwindows = {{ columns = {columns}, rows = {rows}, \
             size = [{:.2}, {:.2}], color = {}, opacity = {:.2}, roughness = {:.2} }}\n",
            point([distance * angle.cos(), 0.0, distance * angle.sin()]),
            // Facing the action: the wall's +z towards the origin.
            (-angle.cos()).atan2(-angle.sin()).to_degrees(),
            point([shade, shade * 0.92, shade * 0.85]),
            range(rng, 0.5, 0.9),
            window[0],
            window[1],
            point(tint),
            range(rng, 0.3, 0.6),
            range(rng, 0.03, 0.15),
        );
    }
}

fn scene_text(
    rng: &mut SplitMix64,
    name: &str,
    family: &Family,
    camera: CameraKind,
    seed: u64,
    wet: bool,
) -> (String, f32) {
    let start_time = (range(rng, 0.0, 3.0) * 100.0).round() / 100.0;
    let mut text = format!(
        "# Generated by `patchex scenes --seed {seed}` ({} split, {} family, {camera:?} camera).\n\
         name = \"{name}\"\nstart_time = {start_time:.2}\n",
        family.split.name(),
        family.name,
    );
    // The characters first: the follow camera needs the first one's name.
    let mut characters = String::new();
    let count = 1 + (rng.next_u64() % 3) as usize;
    for c in 0..count {
        let kind = &family.characters[(rng.next_u64() % family.characters.len() as u64) as usize];
        // The followed character must move; others may stand and play a clip in place.
        let must_move = c == 0 && camera == CameraKind::Follow;
        character(rng, &mut characters, c, kind, must_move);
    }
    let bearing = camera_text(rng, &mut text, camera, start_time);
    sun(rng, &mut text);
    (family.setting)(rng, &mut text, bearing, wet);
    (text + &characters, bearing)
}

fn range(rng: &mut SplitMix64, low: f32, high: f32) -> f32 {
    low + rng.next_f32() * (high - low)
}

fn sign(rng: &mut SplitMix64) -> f32 {
    if rng.next_u64() & 1 == 0 {
        1.0
    } else {
        -1.0
    }
}

fn pick<'a>(rng: &mut SplitMix64, items: &[&'a str]) -> &'a str {
    items[(rng.next_u64() % items.len() as u64) as usize]
}

fn point([x, y, z]: [f32; 3]) -> String {
    format!("[{x:.2}, {y:.2}, {z:.2}]")
}

/// Writes the camera; returns its bearing from the action.
fn camera_text(rng: &mut SplitMix64, text: &mut String, kind: CameraKind, start_time: f32) -> f32 {
    let fov = range(rng, 45.0, 65.0);
    let around = range(rng, 0.0, std::f32::consts::TAU);
    let distance = range(rng, 4.5, 7.5);
    let height = range(rng, 1.2, 2.8);
    let at = |angle: f32, distance: f32, height: f32| {
        [distance * angle.cos(), height, distance * angle.sin()]
    };
    let look = [0.0, 0.9, 0.0];
    text.push_str("\n[camera]\n");
    match kind {
        CameraKind::Orbit => {
            let speed = sign(rng) * range(rng, 20.0, 45.0);
            writeln!(
                text,
                "kind = \"orbit\"\ncenter = {}\nradius = {distance:.2}\nheight = {:.2}\n\
                 degrees_per_second = {speed:.1}\nstart_deg = {:.1}",
                point(look),
                height - 0.9,
                around.to_degrees()
            )
        }
        CameraKind::Strafe | CameraKind::Handheld => {
            // Across the line of sight, a few metres either way of the closest point.
            let (from, reach) = (at(around, distance, height), range(rng, 2.0, 4.0));
            let side = [-around.sin() * reach, 0.0, around.cos() * reach];
            let path = [
                [from[0] - side[0], from[1], from[2] - side[2]],
                [from[0] + side[0], from[1], from[2] + side[2]],
            ];
            let speed = if kind == CameraKind::Strafe {
                range(rng, 1.5, 3.5)
            } else {
                range(rng, 0.3, 0.8)
            };
            writeln!(
                text,
                "kind = \"dolly\"\npath = [{}, {}]\nspeed = {speed:.2}\ntarget = {}",
                point(path[0]),
                point(path[1]),
                point(look)
            )
        }
        CameraKind::Static => writeln!(
            text,
            "kind = \"static\"\nposition = {}\ntarget = {}",
            point(at(around, distance, height)),
            point(look)
        ),
        CameraKind::Follow => writeln!(
            text,
            "kind = \"follow\"\ncharacter = \"c1\"\noffset = {}\nlook_height = {:.2}",
            point([
                range(rng, -0.8, 0.8),
                range(rng, 1.5, 2.2),
                -range(rng, 3.0, 4.5)
            ]),
            range(rng, 0.8, 1.3)
        ),
        CameraKind::Pan => {
            // Faces the action a tenth of a second into the sequence, and keeps turning fast.
            let position = at(around, distance, height);
            let facing = (-position[2]).atan2(-position[0]).to_degrees();
            let speed = sign(rng) * range(rng, 40.0, 90.0);
            writeln!(
                text,
                "kind = \"pan\"\nposition = {}\ndegrees_per_second = {speed:.1}\n\
                 start_deg = {:.1}\npitch_deg = {:.1}",
                point(position),
                facing - (start_time + 0.1) * speed,
                (height - 0.9).atan2(distance).to_degrees()
            )
        }
    }
    .expect("writing to a String");
    let shake = match kind {
        CameraKind::Handheld => Some(range(rng, 0.02, 0.04)),
        CameraKind::Follow if rng.next_u64() & 1 == 0 => Some(range(rng, 0.01, 0.03)),
        _ => None,
    };
    if let Some(amplitude) = shake {
        let frequency = range(rng, 1.2, 2.5);
        writeln!(
            text,
            "shake = {{ amplitude = {amplitude:.3}, frequency = {frequency:.2} }}"
        )
        .expect("writing to a String");
    }
    writeln!(text, "fov_deg = {fov:.1}").expect("writing to a String");
    around
}

fn sun(rng: &mut SplitMix64, text: &mut String) {
    let elevation = range(rng, 18.0, 65.0);
    // Low suns are warmer.
    let warmth = ((65.0 - elevation) / 47.0).clamp(0.0, 1.0);
    let color = [1.0, 0.95 - 0.12 * warmth, 0.88 - 0.2 * warmth];
    writeln!(
        text,
        "\n[sun]\nazimuth_deg = {:.1}\nelevation_deg = {elevation:.1}\ncolor = {}\n\
         intensity = {:.2}\nsky_zenith = [0.25, 0.4, 0.75]\nsky_horizon = {}\n\
         ground_ambient = [0.12, 0.11, 0.1]\nshadow_resolution = 2048",
        range(rng, 0.0, 360.0),
        point(color),
        range(rng, 2.5, 3.6),
        point([
            0.7 + 0.15 * warmth,
            0.8 - 0.05 * warmth,
            0.9 - 0.25 * warmth
        ]),
    )
    .expect("writing to a String");
}

fn character(
    rng: &mut SplitMix64,
    text: &mut String,
    index: usize,
    kind: &CharacterKind,
    must_move: bool,
) {
    let how = rng.next_u64() % 4;
    let (clip, speed) = match (how, kind.run, kind.in_place) {
        (0, Some((clip, speed)), _) => (Some(clip), speed),
        (1, _, Some(clip)) if !must_move => (Some(clip), 0.0),
        _ => kind.walk,
    };
    // A straight walk across the action area, back and forth.
    let mut heading = range(rng, 0.0, std::f32::consts::TAU);
    if kind.travel == Travel::Drives {
        heading = if heading.cos() >= 0.0 { 0.0 } else { PI };
    }
    let offset = range(rng, -1.5, 1.5);
    let half = if speed > 3.0 { 6.0 } else { 3.0 };
    let height = match kind.travel {
        Travel::Flies => range(rng, 1.5, 3.0),
        _ => 0.0,
    };
    let across = [-heading.sin() * offset, height, heading.cos() * offset];
    let ends = [-half, half].map(|s| {
        [
            across[0] + s * heading.cos(),
            height,
            across[2] + s * heading.sin(),
        ]
    });
    let path = if speed == 0.0 {
        format!("[{}]", point(across))
    } else {
        format!("[{}, {}]", point(ends[0]), point(ends[1]))
    };
    let clip = clip.map_or(String::new(), |clip| format!("clip = \"{clip}\"\n"));
    writeln!(
        text,
        "\n[[character]]\nname = \"c{}\"\nasset = \"{}\"\n{clip}clip_offset = {:.2}\n\
         scale = {}\nyaw_offset_deg = {}\nyaw_deg = {:.1}\npath = {path}\nwalk_speed = {speed}",
        index + 1,
        kind.asset,
        range(rng, 0.0, 1.0),
        kind.scale,
        kind.yaw_offset_deg,
        range(rng, 0.0, 360.0),
    )
    .expect("writing to a String");
}

/// Paving for a family's ground: the side of a tile in metres and the tiles' roughness. Fixed
/// per family, so it draws nothing from the scene's random sequence.
struct Paving {
    tile_size: f32,
    roughness: f32,
}

/// Wet ground is glossier: its paving's roughness (or, unpaved, the default 1) times this.
const WET_ROUGHNESS: f32 = 0.4;

fn ground(text: &mut String, height: f32, color: [f32; 3], paving: Option<Paving>, wet: bool) {
    writeln!(
        text,
        "\n[ground]\nsize = 90.0\nheight = {height}\nbase_color = {}",
        point(color)
    )
    .expect("writing to a String");
    let wetness = if wet { WET_ROUGHNESS } else { 1.0 };
    match paving {
        Some(Paving {
            tile_size,
            roughness,
        }) => writeln!(
            text,
            "roughness = {:.2}\ntiles = {{ size = {tile_size} }}",
            roughness * wetness
        ),
        None if wet => writeln!(text, "roughness = {WET_ROUGHNESS}"),
        None => Ok(()),
    }
    .expect("writing to a String");
}

/// An environment piece; `asset` is under `assets/environments/`.
fn prop(text: &mut String, asset: &str, position: [f32; 3], yaw: f32, scale: f32) {
    placed(text, &format!("environments/{asset}"), position, yaw, scale);
}

/// An environment piece; `asset` is under `assets/`.
fn placed(text: &mut String, asset: &str, position: [f32; 3], yaw: f32, scale: f32) {
    writeln!(
        text,
        "\n[[environment]]\nasset = \"{asset}\"\nposition = {}\nyaw_deg = {yaw:.1}\n\
         scale = {scale:.3}",
        point(position)
    )
    .expect("writing to a String");
}

/// A ring of Quaternius nature pieces around the action, drawn by the renderer's own seeded
/// scatter.
fn scatter(
    rng: &mut SplitMix64,
    text: &mut String,
    assets: &[&str],
    count: usize,
    radius: (f32, f32),
    scale: (f32, f32),
) {
    scatter_from(
        rng,
        text,
        "environments/quaternius_nature",
        assets,
        count,
        radius,
        scale,
    );
}

/// A ring of pieces of `folder` (under `assets/`) around the action.
fn scatter_from(
    rng: &mut SplitMix64,
    text: &mut String,
    folder: &str,
    assets: &[&str],
    count: usize,
    radius: (f32, f32),
    scale: (f32, f32),
) {
    let assets: Vec<String> = assets
        .iter()
        .map(|a| format!("\"{folder}/{a}.glb\""))
        .collect();
    writeln!(
        text,
        "\n[[scatter]]\nassets = [{}]\ncount = {count}\ncenter = [0.0, 0.0, 0.0]\n\
         radius_min = {:.1}\nradius_max = {:.1}\nscale_min = {:.2}\nscale_max = {:.2}\nseed = {}",
        assets.join(", "),
        radius.0,
        radius.1,
        scale.0,
        scale.1,
        rng.next_u64() % 1_000_000
    )
    .expect("writing to a String");
}

/// A crossing of the street kit with lights and signs at its corners.
fn street(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(
        text,
        -0.12,
        [0.35, 0.42, 0.28],
        Some(Paving {
            tile_size: 0.5,
            roughness: 0.35,
        }),
        wet,
    );
    let centre = pick(rng, &["Street_4Way", "Street_3Way"]);
    let kit = |piece: &str| format!("quaternius_street/{piece}.glb");
    prop(text, &kit(centre), [0.0, 0.0, 0.0], 0.0, 4.0);
    for (x, z, yaw) in [
        (8.0, 0.0, 0.0),
        (-8.0, 0.0, 0.0),
        (0.0, 8.0, 90.0),
        (0.0, -8.0, 90.0),
    ] {
        let piece = pick(rng, &["Street_Straight", "Street_Straight", "Street_Empty"]);
        prop(text, &kit(piece), [x, 0.0, z], yaw, 4.0);
    }
    let corners = [
        [4.5, 0.0, 4.5],
        [-4.5, 0.0, 4.5],
        [4.5, 0.0, -4.5],
        [-4.5, 0.0, -4.5],
    ];
    for corner in corners {
        let piece = pick(
            rng,
            &[
                "Streetlight_Single",
                "Streetlight_Double",
                "TrafficLight",
                "Sign_Stop",
            ],
        );
        prop(text, &kit(piece), corner, range(rng, 0.0, 360.0), 1.5);
    }
    scatter(
        rng,
        text,
        &["CommonTree_1", "CommonTree_3", "Bush_1"],
        12,
        (11.0, 20.0),
        (1.2, 2.0),
    );
}

/// Thin geometry: trees around (beyond the cameras, which stand at most 8.5 m out), grass and
/// flowers underfoot.
fn forest(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(text, 0.0, [0.3, 0.42, 0.2], None, wet);
    let trees = [
        "CommonTree_1",
        "CommonTree_2",
        "CommonTree_3",
        "PineTree_1",
        "PineTree_2",
        "PineTree_3",
        "BirchTree_1",
        "BirchTree_2",
        "BirchTree_3",
    ];
    let count = 30 + (rng.next_u64() % 30) as usize;
    scatter(rng, text, &trees, count, (9.0, 20.0), (1.2, 2.0));
    let grass = ["Grass", "Grass_2", "Grass_Short", "Flowers"];
    let count = 150 + (rng.next_u64() % 200) as usize;
    scatter(rng, text, &grass, count, (0.0, 8.0), (0.35, 0.75));
    let rocks = ["Bush_1", "Rock_1", "Rock_Moss_2", "Plant_1", "TreeStump"];
    scatter(rng, text, &rocks, 20, (2.0, 10.0), (0.8, 1.4));
}

/// Validation's wood: autumn trees, willows, logs and mossy rocks.
fn autumn(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(
        text,
        0.0,
        [0.42, 0.33, 0.18],
        Some(Paving {
            tile_size: 0.8,
            roughness: 0.45,
        }),
        wet,
    );
    let trees = [
        "CommonTree_Autumn_1",
        "CommonTree_Autumn_2",
        "BirchTree_Autumn_1",
        "PineTree_Autumn_1",
        "Willow_Autumn_1",
        "Willow_Autumn_2",
    ];
    let count = 26 + (rng.next_u64() % 26) as usize;
    scatter(rng, text, &trees, count, (9.0, 20.0), (1.1, 1.9));
    let ground_cover = [
        "WoodLog_Moss",
        "Rock_Moss_1",
        "Bush_2",
        "Plant_3",
        "TreeStump_Moss",
    ];
    let count = 20 + (rng.next_u64() % 20) as usize;
    scatter(rng, text, &ground_cover, count, (1.5, 10.0), (0.7, 1.3));
}

/// Test's desert: cacti, palms and bare rocks, wide and bright.
fn desert(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(
        text,
        0.0,
        [0.72, 0.6, 0.4],
        Some(Paving {
            tile_size: 0.6,
            roughness: 0.55,
        }),
        wet,
    );
    let tall = [
        "Cactus_1",
        "Cactus_2",
        "Cactus_3",
        "PalmTree_1",
        "PalmTree_2",
    ];
    let count = 20 + (rng.next_u64() % 20) as usize;
    scatter(rng, text, &tall, count, (9.0, 18.0), (1.0, 1.8));
    let low = ["CactusFlowers_2", "Rock_2", "Rock_3", "Rock_4"];
    let count = 25 + (rng.next_u64() % 25) as usize;
    scatter(rng, text, &low, count, (1.5, 10.0), (0.6, 1.2));
}

/// Test's city block: the Littlest Tokyo diorama (dense and textured, its own animation not
/// played: environments are static) behind the action, with street furniture in front.
fn tokyo(rng: &mut SplitMix64, text: &mut String, camera_bearing: f32, wet: bool) {
    ground(
        text,
        0.0,
        [0.4, 0.4, 0.42],
        Some(Paving {
            tile_size: 0.4,
            roughness: 0.25,
        }),
        wet,
    );
    // The diorama's lowest point is 2.1 m below its origin at this scale.
    // Behind the action as the camera sees it.
    let yaw = range(rng, 0.0, 360.0);
    let back = camera_bearing + std::f32::consts::PI + range(rng, -0.5, 0.5);
    let place = [5.0 * back.cos(), 2.12, 5.0 * back.sin()];
    prop(text, "LittlestTokyo.glb", place, yaw, 0.01);
    for _ in 0..3 {
        let piece = pick(
            rng,
            &[
                "TrafficLight_2",
                "Streetlight_Triple",
                "Sign_NoParking",
                "Sign_Triangle",
            ],
        );
        let angle = range(rng, 0.0, std::f32::consts::TAU);
        let radius = range(rng, 2.0, 4.0);
        prop(
            text,
            &format!("quaternius_street/{piece}.glb"),
            [radius * angle.cos(), 0.0, radius * angle.sin()],
            range(rng, 0.0, 360.0),
            1.5,
        );
    }
}

/// Kenney's city block: a crossroads of 6 m road tiles through the action, street lights along
/// its outer tiles (beyond the cameras, which the kit's posts at this scale would fill), and
/// houses, garages and tree lots in the four corners beyond the cameras' reach.
fn city(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(
        text,
        -0.02,
        [0.36, 0.45, 0.3],
        Some(Paving {
            tile_size: 0.5,
            roughness: 0.4,
        }),
        wet,
    );
    let kit = |piece: &str| format!("kenney/city/{piece}.glb");
    let tile = 6.0;
    placed(text, &kit("road-intersection"), [0.0; 3], 0.0, tile);
    for step in [1.0, 2.0, -1.0, -2.0] {
        let outer: &[&str] = &["road-straight", "road-straight-lightposts"];
        let pieces = if f32::abs(step) > 1.0 {
            outer
        } else {
            &outer[..1]
        };
        let piece = pick(rng, pieces);
        placed(text, &kit(piece), [step * tile, 0.0, 0.0], 90.0, tile);
        let piece = pick(rng, pieces);
        placed(text, &kit(piece), [0.0, 0.0, step * tile], 0.0, tile);
    }
    let lots = [
        "building-small-a",
        "building-small-b",
        "building-small-c",
        "building-small-d",
        "building-garage",
        "grass-trees",
        "grass-trees-tall",
        "pavement-fountain",
    ];
    for (x, z) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
        for (near, far) in [(1.5, 1.5), (1.5, 2.5), (2.5, 1.5)] {
            let yaw = 90.0 * (rng.next_u64() % 4) as f32;
            let position = [x * near * tile + tile / 2.0 * x, 0.0, z * far * tile];
            placed(text, &kit(pick(rng, &lots)), position, yaw, tile);
        }
    }
}

/// Kenney's race track: a straight of 10 m track pieces along x through the action, with the
/// kit's forest and tent pieces in rows either side.
fn racing(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(text, 0.0, [0.38, 0.5, 0.28], None, wet);
    let kit = |piece: &str| format!("kenney/racing/{piece}.glb");
    for step in -2..=2 {
        let x = 10.0 * step as f32;
        let piece = match step {
            0 => pick(rng, &["track-straight", "track-finish"]),
            _ => "track-straight",
        };
        placed(text, &kit(piece), [x, 0.0, 0.0], 90.0, 1.0);
        for side in [-1.0, 1.0] {
            let decoration = pick(
                rng,
                &["decoration-forest", "decoration-tents", "decoration-empty"],
            );
            let yaw = if side > 0.0 { 0.0 } else { 180.0 };
            placed(text, &kit(decoration), [x, 0.0, 15.0 * side], yaw, 1.0);
        }
    }
}

/// Validation's platforms: grassy islands of Kenney's platformer kit around the action, bricks,
/// coin blocks and flags on them, and clouds overhead.
fn platforms(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(
        text,
        0.0,
        [0.45, 0.62, 0.32],
        Some(Paving {
            tile_size: 1.0,
            roughness: 0.5,
        }),
        wet,
    );
    let folder = "kenney/platformer";
    let islands = [
        "platform-grass-large-round",
        "platform-large",
        "platform-medium",
        "platform",
    ];
    let count = 8 + (rng.next_u64() % 6) as usize;
    scatter_from(rng, text, folder, &islands, count, (9.0, 16.0), (1.0, 1.6));
    let pieces = ["brick", "block-coin", "flag", "grass", "grass-small"];
    let count = 10 + (rng.next_u64() % 10) as usize;
    scatter_from(rng, text, folder, &pieces, count, (3.0, 9.0), (0.8, 1.3));
    for _ in 0..4 {
        let angle = range(rng, 0.0, std::f32::consts::TAU);
        let radius = range(rng, 6.0, 14.0);
        let position = [
            radius * angle.cos(),
            range(rng, 5.0, 8.0),
            radius * angle.sin(),
        ];
        placed(text, &format!("{folder}/cloud.glb"), position, 0.0, 2.0);
    }
}

/// Test's arena: Kenney's FPS kit, high and low walls for cover around the action, raised
/// grassy platforms beyond, drones overhead.
fn arena(rng: &mut SplitMix64, text: &mut String, _: f32, wet: bool) {
    ground(
        text,
        0.0,
        [0.5, 0.5, 0.48],
        Some(Paving {
            tile_size: 1.2,
            roughness: 0.3,
        }),
        wet,
    );
    let folder = "kenney/fps";
    // Low cover among the action, which the cameras see over; high walls behind them.
    let count = 4 + (rng.next_u64() % 4) as usize;
    scatter_from(
        rng,
        text,
        folder,
        &["wall-low"],
        count,
        (2.5, 6.0),
        (1.0, 1.3),
    );
    let count = 6 + (rng.next_u64() % 6) as usize;
    scatter_from(
        rng,
        text,
        folder,
        &["wall-high"],
        count,
        (8.5, 12.0),
        (1.2, 1.6),
    );
    let count = 6 + (rng.next_u64() % 4) as usize;
    let raised = ["platform-large-grass", "platform"];
    scatter_from(rng, text, folder, &raised, count, (10.0, 16.0), (1.0, 1.5));
    let count = 30 + (rng.next_u64() % 30) as usize;
    scatter_from(
        rng,
        text,
        folder,
        &["grass", "grass-small"],
        count,
        (1.0, 9.0),
        (1.0, 2.0),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneDescription;

    #[test]
    fn the_set_is_reproducible_and_every_file_parses() {
        let first = generate_set(1);
        let second = generate_set(1);
        assert!(first.len() >= 20);
        for (a, b) in first.iter().zip(&second) {
            assert_eq!(a.text, b.text);
            let scene: SceneDescription = toml::from_str(&a.text)
                .unwrap_or_else(|e| panic!("{} does not parse: {e}\n{}", a.name, a.text));
            assert_eq!(scene.name, a.name);
            assert!(!scene.character.is_empty());
        }
        assert_ne!(first[0].text, generate_set(2)[0].text);
        for split in [Split::Training, Split::Validation, Split::Test] {
            assert!(first.iter().any(|s| s.split == split), "{split:?} is empty");
        }
    }

    #[test]
    fn the_committed_set_is_what_seed_1_writes() {
        let folder =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/generated");
        for scene in generate_set(1) {
            let path = folder.join(format!("{}.toml", scene.name));
            let committed = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e}; run `patchex scenes`", path.display()));
            assert_eq!(
                committed,
                scene.text,
                "{} is stale; run `patchex scenes`",
                path.display()
            );
        }
    }

    /// Every asset file a scene names, characters and environment pieces alike.
    fn assets_named(text: &str) -> Vec<&str> {
        text.split('"')
            .filter(|piece| piece.ends_with(".glb"))
            .collect()
    }

    #[test]
    fn no_asset_of_a_validation_or_test_scene_is_in_training() {
        let set = generate_set(1);
        let training: std::collections::HashSet<&str> = set
            .iter()
            .filter(|s| s.split == Split::Training)
            .flat_map(|s| assets_named(&s.text))
            .collect();
        for scene in set.iter().filter(|s| s.split != Split::Training) {
            for asset in assets_named(&scene.text) {
                assert!(
                    !training.contains(asset),
                    "{} ({:?}) shares {asset} with training",
                    scene.name,
                    scene.split
                );
            }
        }
    }

    #[test]
    fn splits_share_no_setting_asset_or_camera_kind_with_training() {
        let training: Vec<&Family> = FAMILIES
            .iter()
            .filter(|f| f.split == Split::Training)
            .collect();
        for family in FAMILIES.iter().filter(|f| f.split != Split::Training) {
            for kind in family.characters {
                assert!(
                    training
                        .iter()
                        .all(|t| t.characters.iter().all(|c| c.asset != kind.asset)),
                    "{} shares {} with training",
                    family.name,
                    kind.asset
                );
            }
            assert!(
                family
                    .cameras
                    .iter()
                    .any(|c| training.iter().all(|t| !t.cameras.contains(c))),
                "{} has no camera kind that training lacks",
                family.name
            );
        }
    }
}
