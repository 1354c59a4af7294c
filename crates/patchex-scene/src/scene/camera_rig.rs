//! Where each camera rig of the scene format puts the camera at an instant.

use super::camera::CameraState;
use super::description::CameraRig;
use super::path::PathMotion;
use super::World;
use glam::{Quat, Vec3};

impl World {
    /// The camera at `time` for a viewport of the given aspect ratio (width / height).
    pub fn camera(&self, time: f32, aspect: f32) -> CameraState {
        let lens = &self.description.camera;
        let (mut position, mut target) = match &lens.rig {
            CameraRig::Static { position, target } => (Vec3::from(*position), Vec3::from(*target)),
            CameraRig::Orbit {
                center,
                radius,
                height,
                degrees_per_second,
                start_deg,
            } => {
                let angle = (start_deg + degrees_per_second * time).to_radians();
                let center = Vec3::from(*center);
                (
                    center + Vec3::new(radius * angle.cos(), *height, radius * angle.sin()),
                    center,
                )
            }
            CameraRig::Dolly {
                path,
                speed,
                target,
            } => (
                PathMotion::new(path).at(speed * time).0,
                Vec3::from(*target),
            ),
            CameraRig::Pan {
                position,
                degrees_per_second,
                start_deg,
                pitch_deg,
            } => {
                let (yaw, pitch) = (
                    (start_deg + degrees_per_second * time).to_radians(),
                    pitch_deg.to_radians(),
                );
                let position = Vec3::from(*position);
                let ahead = Vec3::new(
                    yaw.cos() * pitch.cos(),
                    -pitch.sin(),
                    yaw.sin() * pitch.cos(),
                );
                (position, position + ahead)
            }
            CameraRig::Follow {
                character,
                offset,
                look_height,
            } => {
                let followed = self
                    .characters
                    .iter()
                    .find(|c| &c.description.name == character)
                    .expect("checked when the world was built");
                let (_, rotation, translation) = self
                    .character_transform(followed, time)
                    .to_scale_rotation_translation();
                let yaw_only =
                    Quat::from_rotation_y(-followed.description.yaw_offset_deg.to_radians())
                        * rotation;
                (
                    translation + yaw_only * Vec3::from(*offset),
                    translation + Vec3::Y * *look_height,
                )
            }
        };
        if let Some(shake) = lens.shake {
            let phase = std::f32::consts::TAU * shake.frequency * time;
            let wobble = Vec3::new(
                phase.sin() + 0.5 * (2.3 * phase + 1.1).sin(),
                (1.3 * phase + 2.0).sin() + 0.4 * (3.1 * phase).sin(),
                (0.7 * phase + 0.5).sin(),
            ) * shake.amplitude;
            position += wobble;
            target += wobble * 0.5;
        }
        CameraState::look_at(position, target, lens.fov_deg, aspect, lens.near, lens.far)
    }
}
