//! The scene Bevy renders: three animated glTF characters from the project's assets running
//! circles on a tiled ground among a few blocks, a sun with shadows, and a camera that moves.
//! Everything moves with `Time`, so a displayed instant is a function of its index alone.

use std::f32::consts::TAU;

use bevy::asset::RenderAssetUsages;
use bevy::camera::{CameraMainTextureUsages, Hdr, RenderTarget};
use bevy::core_pipeline::prepass::{
    DeferredPrepass, DepthPrepass, MotionVectorPrepass, NormalPrepass,
};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::gltf::Gltf;
use bevy::image::{ImageAddressMode, ImageSampler, ImageSamplerDescriptor};
use bevy::light::CascadeShadowConfigBuilder;
use bevy::math::Affine2;
use bevy::pbr::DefaultOpaqueRendererMethod;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat, TextureUsages};
use bevy::world_serialization::{WorldAssetRoot, WorldInstanceReady};

pub struct ScenePlugin {
    pub width: u32,
    pub height: u32,
}

/// How many animated characters the scene holds.
pub const CHARACTERS: usize = 3;

/// A character running a circle: its glTF, the clip it plays and its circle.
#[derive(Component, Clone)]
struct Runner {
    gltf: Handle<Gltf>,
    /// The name of the animation it plays.
    clip: &'static str,
    scale: f32,
    centre: Vec2,
    radius: f32,
    /// Radians per second, signed: the direction it runs.
    angular_speed: f32,
    phase: f32,
}

/// The size of the frames the camera renders.
#[derive(Resource, Clone, Copy)]
struct FrameSize(UVec2);

impl Plugin for ScenePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(DefaultOpaqueRendererMethod::deferred())
            .insert_resource(GlobalAmbientLight {
                color: Color::WHITE,
                brightness: 150.0,
                ..default()
            })
            .insert_resource(FrameSize(UVec2::new(self.width, self.height)))
            .add_systems(Startup, setup)
            .add_systems(Update, (spawn_loaded_runners, run_circles, move_camera));
    }
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut images: ResMut<Assets<Image>>,
    assets: Res<AssetServer>,
    size: Res<FrameSize>,
) {
    let target = images.add(Image::new_target_texture(
        size.0.x,
        size.0.y,
        TextureFormat::Rgba16Float,
        None,
    ));

    commands.spawn((
        Camera3d::default(),
        Hdr,
        RenderTarget::Image(target.into()),
        Tonemapping::None,
        Msaa::Off,
        DepthPrepass,
        NormalPrepass,
        MotionVectorPrepass,
        DeferredPrepass,
        // patchex's output is copied over the view's colour, which the check copies out.
        CameraMainTextureUsages::default().with(TextureUsages::COPY_SRC | TextureUsages::COPY_DST),
        camera_transform(0.0),
    ));

    commands.spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            illuminance: 10_000.0,
            ..default()
        },
        Transform::from_xyz(-4.0, 5.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
        CascadeShadowConfigBuilder {
            first_cascade_far_bound: 12.0,
            maximum_distance: 40.0,
            ..default()
        }
        .build(),
    ));

    let tiles = images.add(tile_texture());
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(60.0, 60.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color_texture: Some(tiles),
            uv_transform: Affine2::from_scale(Vec2::splat(30.0)),
            perceptual_roughness: 0.8,
            ..default()
        })),
    ));
    for (position, size, colour) in [
        (
            Vec3::new(-3.0, 0.75, -2.5),
            Vec3::new(1.0, 1.5, 1.0),
            Color::srgb(0.75, 0.3, 0.2),
        ),
        (
            Vec3::new(2.5, 0.5, -3.0),
            Vec3::new(2.0, 1.0, 0.8),
            Color::srgb(0.25, 0.45, 0.7),
        ),
        (
            Vec3::new(0.5, 1.0, 3.5),
            Vec3::new(0.6, 2.0, 0.6),
            Color::srgb(0.8, 0.75, 0.3),
        ),
    ] {
        commands.spawn((
            Mesh3d(meshes.add(Cuboid::from_size(size))),
            MeshMaterial3d(materials.add(StandardMaterial {
                base_color: colour,
                perceptual_roughness: 0.6,
                ..default()
            })),
            Transform::from_translation(position),
        ));
    }

    let character = |path: &str| assets.load::<Gltf>(format!("characters/{path}"));
    for runner in [
        Runner {
            gltf: character("Fox.glb"),
            clip: "Run",
            scale: 0.012,
            centre: Vec2::new(0.0, 0.0),
            radius: 2.2,
            angular_speed: 1.6,
            phase: 0.0,
        },
        Runner {
            gltf: character("cyberpunk_Character.glb"),
            clip: "CharacterArmature|Run",
            scale: 1.0,
            centre: Vec2::new(0.5, 0.0),
            radius: 2.8,
            angular_speed: -1.1,
            phase: 2.0,
        },
        Runner {
            gltf: character("platformer_Character.glb"),
            clip: "CharacterArmature|Walk",
            scale: 0.5,
            centre: Vec2::new(-1.0, 0.5),
            radius: 1.2,
            angular_speed: 0.9,
            phase: 4.0,
        },
    ] {
        commands.spawn((runner, Transform::default(), Visibility::default()));
    }
}

/// Grey tiles with dark grooves: texture detail for the warp to keep.
fn tile_texture() -> Image {
    const SIDE: u32 = 64;
    let texels = (0..SIDE * SIDE).flat_map(|i| {
        let (x, y) = (i % SIDE, i / SIDE);
        let groove = x % 32 < 2 || y % 32 < 2;
        let shade = if groove {
            60
        } else if (x / 32 + y / 32) % 2 == 0 {
            200
        } else {
            165
        };
        [shade, shade, (shade as f32 * 0.92) as u8, 255]
    });
    let mut image = Image::new(
        Extent3d {
            width: SIDE,
            height: SIDE,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        texels.collect(),
        TextureFormat::Rgba8UnormSrgb,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.sampler = ImageSampler::Descriptor(ImageSamplerDescriptor {
        address_mode_u: ImageAddressMode::Repeat,
        address_mode_v: ImageAddressMode::Repeat,
        ..ImageSamplerDescriptor::linear()
    });
    image
}

/// Spawns each runner's glTF scene once its file has loaded, with the clip it plays.
fn spawn_loaded_runners(
    mut commands: Commands,
    runners: Query<(Entity, &Runner), Without<WorldAssetRoot>>,
    gltfs: Res<Assets<Gltf>>,
    mut graphs: ResMut<Assets<AnimationGraph>>,
) {
    for (entity, runner) in &runners {
        let Some(gltf) = gltfs.get(&runner.gltf) else {
            continue;
        };
        let clip = gltf.named_animations.get(runner.clip).cloned();
        let (Some(scene), Some(clip)) = (gltf.scenes.first().cloned(), clip) else {
            panic!("a character's glTF lacks its scene or clip");
        };
        let (graph, node) = AnimationGraph::from_clip(clip);
        let graph = graphs.add(graph);
        commands
            .entity(entity)
            .insert(WorldAssetRoot(scene))
            .observe(
                move |ready: On<WorldInstanceReady>,
                      mut commands: Commands,
                      children: Query<&Children>,
                      mut players: Query<&mut AnimationPlayer>| {
                    for child in children.iter_descendants(ready.entity) {
                        if let Ok(mut player) = players.get_mut(child) {
                            player.play(node).repeat();
                            commands
                                .entity(child)
                                .insert(AnimationGraphHandle(graph.clone()));
                        }
                    }
                },
            );
    }
}

fn run_circles(time: Res<Time>, mut runners: Query<(&Runner, &mut Transform)>) {
    let seconds = time.elapsed_secs();
    for (runner, mut transform) in &mut runners {
        let angle = runner.phase + runner.angular_speed * seconds;
        let position = runner.centre + runner.radius * Vec2::new(angle.cos(), angle.sin());
        // The tangent of the circle, the way it runs.
        let heading = runner.angular_speed.signum() * Vec2::new(-angle.sin(), angle.cos());
        *transform = Transform::from_xyz(position.x, 0.0, position.y)
            .looking_to(Vec3::new(-heading.x, 0.0, -heading.y), Vec3::Y)
            .with_scale(Vec3::splat(runner.scale));
        // glTF characters face +z; `looking_to` points -z along the heading.
        transform.rotate_y(TAU / 2.0);
    }
}

fn move_camera(time: Res<Time>, mut cameras: Query<&mut Transform, With<Camera3d>>) {
    for mut transform in &mut cameras {
        *transform = camera_transform(time.elapsed_secs());
    }
}

/// A slow orbit that also rises and falls, always looking at the middle of the ground.
fn camera_transform(seconds: f32) -> Transform {
    let angle = 0.6 + 0.35 * seconds;
    let height = 3.2 + 0.8 * (0.7 * seconds).sin();
    Transform::from_xyz(8.0 * angle.cos(), height, 8.0 * angle.sin())
        .looking_at(Vec3::new(0.0, 0.6, 0.0), Vec3::Y)
}
