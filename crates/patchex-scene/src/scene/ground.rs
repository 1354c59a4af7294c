//! Height of the walkable ground under a point, so characters stand on uneven terrain.
//! Triangles are bucketed in a uniform grid over x/z; a query tests one cell.

use glam::{Vec2, Vec3};

const CELL_SIZE: f32 = 1.0;

pub struct GroundSurface {
    triangles: Vec<[Vec3; 3]>,
    origin: Vec2,
    columns: usize,
    rows: usize,
    /// Triangle indices overlapping each cell, row-major.
    cells: Vec<Vec<u32>>,
}

impl GroundSurface {
    pub fn new(triangles: Vec<[Vec3; 3]>) -> Self {
        let xz = |p: Vec3| Vec2::new(p.x, p.z);
        let (lo, hi) = triangles
            .iter()
            .flatten()
            .fold((Vec2::MAX, Vec2::MIN), |(lo, hi), &p| {
                (lo.min(xz(p)), hi.max(xz(p)))
            });
        let (origin, extent) = if triangles.is_empty() {
            (Vec2::ZERO, Vec2::ZERO)
        } else {
            (lo, hi - lo)
        };
        let columns = (extent.x / CELL_SIZE).floor() as usize + 1;
        let rows = (extent.y / CELL_SIZE).floor() as usize + 1;
        let mut cells = vec![Vec::new(); columns * rows];
        let cell_of = |p: Vec2| {
            let c = ((p - origin) / CELL_SIZE).floor();
            (
                (c.x.max(0.0) as usize).min(columns - 1),
                (c.y.max(0.0) as usize).min(rows - 1),
            )
        };
        for (index, triangle) in triangles.iter().enumerate() {
            let (tlo, thi) = triangle
                .iter()
                .fold((Vec2::MAX, Vec2::MIN), |(lo, hi), &p| {
                    (lo.min(xz(p)), hi.max(xz(p)))
                });
            let ((x0, z0), (x1, z1)) = (cell_of(tlo), cell_of(thi));
            for z in z0..=z1 {
                for x in x0..=x1 {
                    cells[z * columns + x].push(index as u32);
                }
            }
        }
        Self {
            triangles,
            origin,
            columns,
            rows,
            cells,
        }
    }

    /// The highest ground surface at (x, z), if the ground covers that point.
    pub fn height_at(&self, x: f32, z: f32) -> Option<f32> {
        let cell = ((Vec2::new(x, z) - self.origin) / CELL_SIZE).floor();
        if self.triangles.is_empty() || cell.x < 0.0 || cell.y < 0.0 {
            return None;
        }
        let (column, row) = (cell.x as usize, cell.y as usize);
        if column >= self.columns || row >= self.rows {
            return None;
        }
        self.cells[row * self.columns + column]
            .iter()
            .filter_map(|&index| height_in_triangle(&self.triangles[index as usize], x, z))
            .reduce(f32::max)
    }
}

/// Height of the triangle's plane at (x, z) when that point lies inside its x/z projection.
fn height_in_triangle([a, b, c]: &[Vec3; 3], x: f32, z: f32) -> Option<f32> {
    let (ab, ac, ap) = (
        Vec2::new(b.x - a.x, b.z - a.z),
        Vec2::new(c.x - a.x, c.z - a.z),
        Vec2::new(x - a.x, z - a.z),
    );
    let determinant = ab.perp_dot(ac);
    if determinant.abs() < 1e-12 {
        return None;
    }
    let v = ap.perp_dot(ac) / determinant;
    let w = ab.perp_dot(ap) / determinant;
    let epsilon = 1e-5;
    if v < -epsilon || w < -epsilon || v + w > 1.0 + epsilon {
        return None;
    }
    Some(a.y + v * (b.y - a.y) + w * (c.y - a.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_follows_a_slope_and_is_absent_off_the_ground() {
        // A 4 m square ramp rising 1 m along +x, as two triangles.
        let (p00, p40, p44, p04) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 1.0, 0.0),
            Vec3::new(4.0, 1.0, 4.0),
            Vec3::new(0.0, 0.0, 4.0),
        );
        let ground = GroundSurface::new(vec![[p00, p40, p44], [p00, p44, p04]]);
        assert!((ground.height_at(2.0, 1.0).unwrap() - 0.5).abs() < 1e-6);
        assert!((ground.height_at(3.0, 3.5).unwrap() - 0.75).abs() < 1e-6);
        assert_eq!(ground.height_at(5.0, 1.0), None);
        assert_eq!(ground.height_at(-0.5, 1.0), None);
    }

    #[test]
    fn the_highest_overlapping_surface_wins() {
        let flat = |y: f32| {
            [
                Vec3::new(0.0, y, 0.0),
                Vec3::new(2.0, y, 0.0),
                Vec3::new(0.0, y, 2.0),
            ]
        };
        let ground = GroundSurface::new(vec![flat(0.0), flat(1.5)]);
        assert_eq!(ground.height_at(0.5, 0.5), Some(1.5));
    }
}
