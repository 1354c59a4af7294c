//! Motion along a closed polyline at constant speed: where a character or dolly camera is at
//! a given time and which way it faces.

use glam::Vec3;

pub struct PathMotion {
    points: Vec<Vec3>,
    /// Distance from the first point to the start of each segment; the last segment closes
    /// the loop back to the first point.
    starts: Vec<f32>,
    length: f32,
}

impl PathMotion {
    pub fn new(points: &[[f32; 3]]) -> Self {
        let points: Vec<Vec3> = points.iter().copied().map(Vec3::from).collect();
        let mut starts = Vec::with_capacity(points.len());
        let mut length = 0.0;
        for (i, point) in points.iter().enumerate() {
            starts.push(length);
            length += point.distance(points[(i + 1) % points.len()]);
        }
        Self {
            points,
            starts,
            length,
        }
    }

    /// Position and unit horizontal heading after travelling `distance` (wrapping).
    pub fn at(&self, distance: f32) -> (Vec3, Vec3) {
        if self.points.len() < 2 || self.length <= 0.0 {
            let position = self.points.first().copied().unwrap_or(Vec3::ZERO);
            return (position, Vec3::Z);
        }
        let d = distance.rem_euclid(self.length);
        let segment = self.starts.partition_point(|&start| start <= d) - 1;
        let a = self.points[segment];
        let b = self.points[(segment + 1) % self.points.len()];
        let segment_length = a.distance(b);
        let t = if segment_length > 0.0 {
            (d - self.starts[segment]) / segment_length
        } else {
            0.0
        };
        let heading = Vec3::new(b.x - a.x, 0.0, b.z - a.z)
            .try_normalize()
            .unwrap_or(Vec3::Z);
        (a.lerp(b, t), heading)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_the_closed_loop_and_wraps() {
        let path = PathMotion::new(&[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.0, 0.0, 3.0]]);
        // Perimeter 4 + 3 + 5 = 12.
        let (p, heading) = path.at(2.0);
        assert!(p.abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-6));
        assert!(heading.abs_diff_eq(Vec3::X, 1e-6));
        let (p, heading) = path.at(5.0);
        assert!(p.abs_diff_eq(Vec3::new(4.0, 0.0, 1.0), 1e-6));
        assert!(heading.abs_diff_eq(Vec3::Z, 1e-6));
        let (p, _) = path.at(12.0 + 2.0);
        assert!(p.abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-5));
    }

    #[test]
    fn single_point_stands_still() {
        let path = PathMotion::new(&[[1.0, 2.0, 3.0]]);
        assert_eq!(path.at(7.0).0, Vec3::new(1.0, 2.0, 3.0));
    }
}
