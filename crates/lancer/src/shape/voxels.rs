//! lancer's voxel grid (`Shape "voxels"`, the lecture's "minecraft"): a dense grid of palette
//! indices, one byte per cell (0 = empty), traversed with a 3D DDA (Amanatides & Woo, "A Fast
//! Voxel Traversal Algorithm for Ray Tracing", 1987) on two levels: 8³ bricks first, so that
//! empty space is crossed eight cells at a time, then the cells of each occupied brick.
//!
//! **Units and axes.** One voxel is one unit of object space. Cell (x, y, z) occupies
//! [x − nx/2, x + 1 − nx/2] × [y − ny/2, y + 1 − ny/2] × [z, z + 1]: the grid is centred in x
//! and y and stands on z = 0. The axes are MagicaVoxel's, where z is up, as for
//! pbrt's quadrics (whose axis is z too): in pbrt's usual y-up scenes a model is stood up by
//! its transform (`Rotate -90 1 0 0`), lancer does not swap axes behind the user's back.
//!
//! **Hits.** A ray entering a filled cell hits the face it enters through; normals point out of
//! the filled cell (flipped by `ReverseOrientation` as for every shape). A ray starting inside
//! a filled cell (which spawned rays never do) hits that cell's exit face. The hit carries the
//! cell's palette colour, which a `diffuse` material uses as its reflectance.
//!
//! A voxel grid is not an emitter: `Scene::build` refuses an area light on it.

use super::hit::{ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, HeldBytes, Placing, ShapeKind};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::Placement;
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Rgb, Vec2, Vec3, gamma, normalize};
use crate::ray::Ray;
use glam::DVec3;
use std::collections::HashSet;
use std::sync::Arc;

/// Side of a brick, in cells: the coarse level of the traversal.
pub const BRICK: u32 = 8;

/// A dense voxel grid and its palette (what a `.vox` file or inline parameters describe).
#[derive(Clone, PartialEq)]
pub struct VoxelGrid {
    dims: [u32; 3],
    cells: Vec<u8>,
    palette: Box<[Rgb; 256]>,
}

impl std::fmt::Debug for VoxelGrid {
    /// Dimensions, filled count and a digest of the cells and palette (the cells may be
    /// millions).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::math::digest::Digest;
        f.debug_struct("VoxelGrid")
            .field("dims", &self.dims)
            .field("filled", &self.filled_count())
            .field("cells", &Digest(&self.cells))
            .field("palette", &Digest(&self.palette[..]))
            .finish()
    }
}

impl VoxelGrid {
    /// A grid of `dims` = (nx, ny, nz) cells, `cells[x + nx·(y + ny·z)]` the palette index of
    /// cell (x, y, z) (0 = empty), `palette[i]` the linear RGB reflectance of index i (entry 0
    /// is unused). Fails when a dimension is 0, the grid has 2³¹ cells or more, or `cells` is
    /// not nx·ny·nz long.
    pub fn new(dims: [u32; 3], cells: Vec<u8>, palette: [Rgb; 256]) -> Result<VoxelGrid, String> {
        if dims.contains(&0) {
            return Err(format!(
                "voxel grid dimensions {dims:?} must all be positive"
            ));
        }
        let count = dims.iter().map(|&d| d as u64).product::<u64>();
        if count >= 1 << 31 {
            return Err(format!(
                "voxel grid {}×{}×{} has {count} cells, more than lancer's limit of 2³¹",
                dims[0], dims[1], dims[2]
            ));
        }
        if cells.len() as u64 != count {
            return Err(format!(
                "voxel grid {}×{}×{} needs {count} cells, got {}",
                dims[0],
                dims[1],
                dims[2],
                cells.len()
            ));
        }
        Ok(VoxelGrid {
            dims,
            cells,
            palette: Box::new(palette),
        })
    }

    /// Cells along x, y and z.
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    /// Palette indices, x fastest then y then z.
    pub fn cells(&self) -> &[u8] {
        &self.cells
    }

    /// Linear RGB reflectance per palette index (entry 0 unused).
    pub fn palette(&self) -> &[Rgb; 256] {
        &self.palette
    }

    /// Linear index of cell (x, y, z): x + nx·(y + ny·z).
    #[inline]
    pub fn index(&self, x: u32, y: u32, z: u32) -> usize {
        x as usize + self.dims[0] as usize * (y as usize + self.dims[1] as usize * z as usize)
    }

    /// Palette index of cell (x, y, z) (0 = empty).
    #[inline]
    pub fn get(&self, x: u32, y: u32, z: u32) -> u8 {
        self.cells[self.index(x, y, z)]
    }

    /// Number of filled cells.
    pub fn filled_count(&self) -> usize {
        self.cells.iter().filter(|&&c| c != 0).count()
    }

    /// Offset from object space to grid space (where cell (x, y, z) is [x, x+1]×…):
    /// (nx/2, ny/2, 0).
    pub fn grid_offset(&self) -> Vec3 {
        Vec3::new(self.dims[0] as f32 * 0.5, self.dims[1] as f32 * 0.5, 0.0)
    }

    /// Heap bytes held: one per cell plus the palette.
    pub fn heap_bytes(&self) -> usize {
        self.cells.capacity() + std::mem::size_of::<[Rgb; 256]>()
    }
}

/// sRGB transfer function inverted, for 8-bit palette entries: c = v/255, linear =
/// c/12.92 when c ≤ 0.04045, else ((c + 0.055)/1.055)^2.4 (IEC 61966-2-1).
pub fn srgb8_to_linear(v: u8) -> f32 {
    let c = v as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Where a ray's traversal stopped, grid space.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GridHit {
    t: f64,
    cell: [i32; 3],
    /// Axis of the face hit, + 3 for the cell's max face.
    face: usize,
}

/// One step of a DDA walk: the cell, the parametric interval the ray spends in it, the axis it
/// came in through (`None` for the walk's first cell when the ray starts inside the range)
/// and the axis it leaves through.
#[derive(Clone, Copy, Debug)]
struct Step {
    cell: [i32; 3],
    t_in: f64,
    axis_in: Option<usize>,
    t_out: f64,
    axis_out: usize,
}

/// A voxel grid placed in the world (`Shape::Voxels`).
#[derive(Clone, Debug, PartialEq)]
pub struct Voxels {
    grid: Arc<VoxelGrid>,
    /// 1 where the 8³ brick holds a filled cell, bricks x fastest.
    bricks: Vec<u8>,
    brick_dims: [i32; 3],
    /// Box of the filled cells, grid space, in cells: [lo, hi).
    lo: [i32; 3],
    hi: [i32; 3],
    offset: DVec3,
    /// Placement in the world.
    pub placement: Placement,
}

impl Voxels {
    /// The grid placed by `placement`; `None` when no cell is filled.
    pub fn new(placement: Placement, grid: Arc<VoxelGrid>) -> Option<Voxels> {
        let [nx, ny, nz] = grid.dims;
        let bd = [nx, ny, nz].map(|n| n.div_ceil(BRICK) as i32);
        let mut bricks = vec![0u8; (bd[0] * bd[1] * bd[2]) as usize];
        let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
        for z in 0..nz {
            for y in 0..ny {
                let row = grid.index(0, y, z);
                for (x, &c) in grid.cells[row..row + nx as usize].iter().enumerate() {
                    if c != 0 {
                        let p = [x as i32, y as i32, z as i32];
                        let b = p.map(|v| v / BRICK as i32);
                        bricks[(b[0] + bd[0] * (b[1] + bd[1] * b[2])) as usize] = 1;
                        for k in 0..3 {
                            lo[k] = lo[k].min(p[k]);
                            hi[k] = hi[k].max(p[k] + 1);
                        }
                    }
                }
            }
        }
        if lo[0] > hi[0] {
            return None;
        }
        Some(Voxels {
            offset: grid.grid_offset().as_dvec3(),
            grid,
            bricks,
            brick_dims: bd,
            lo,
            hi,
            placement,
        })
    }

    /// The grid.
    pub fn grid(&self) -> &VoxelGrid {
        &self.grid
    }

    /// Heap bytes of this shape, the shared grid included: the cells (one byte each), one
    /// byte per brick of 8³ cells, the palette.
    pub fn heap_bytes(&self) -> usize {
        self.grid.heap_bytes() + self.bricks.capacity()
    }

    /// Object-space box of the filled cells.
    pub fn object_bounds(&self) -> Bounds3 {
        let off = self.offset.as_vec3a();
        let lo = Vec3::new(self.lo[0] as f32, self.lo[1] as f32, self.lo[2] as f32) - off;
        let hi = Vec3::new(self.hi[0] as f32, self.hi[1] as f32, self.hi[2] as f32) - off;
        Bounds3::new(lo, hi)
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        self.placement.to_world.bounds(&self.object_bounds())
    }

    /// Nearest hit: the ray moved to grid space in double precision, clipped to the box of
    /// the filled cells, then walked brick by brick and cell by cell. `u` holds
    /// 8·(palette index) + face (face = axis, + 3 for a max face), `v` the cell's linear index
    /// as the bits of an `f32` (exact for any index below 2³¹, never a NaN).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let h = self.march(o + self.offset, d, ray.t_max as f64)?;
        let [x, y, z] = h.cell.map(|c| c as u32);
        let index = self.grid.index(x, y, z);
        let palette = self.grid.cells[index] as usize;
        let t = h.t as f32;
        // The rounding to f32 must not take the hit out of (0, t_max).
        if t <= 0.0 || t >= ray.t_max {
            return None;
        }
        Some(ShapeHit {
            t,
            u: (palette * 8 + h.face) as f32,
            v: f32::from_bits(index as u32),
        })
    }

    /// The cell (x, y, z) a hit of [`Voxels::intersect`] found.
    pub fn hit_cell(&self, hit: &ShapeHit) -> [u32; 3] {
        let index = hit.v.to_bits() as usize;
        let [nx, ny, _] = self.grid.dims.map(|n| n as usize);
        [
            (index % nx) as u32,
            (index / nx % ny) as u32,
            (index / (nx * ny)) as u32,
        ]
    }

    /// The reflectance of the cell a hit found: its palette colour.
    #[inline]
    pub fn hit_albedo(&self, hit: &ShapeHit) -> Rgb {
        self.grid.palette[(hit.u as usize / 8).min(255)]
    }

    /// The traversal in grid space: `o + t·d` for 0 < t < `t_max`.
    fn march(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<GridHit> {
        let inv = d.recip();
        // Slab test against the filled box: on axis k the ray is between its planes for
        // t ∈ [(lo − o)/d, (hi − o)/d] (ordered).
        let (mut t_near, mut t_far) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut near_axis = 0;
        for k in 0..3 {
            let (lo, hi) = (self.lo[k] as f64, self.hi[k] as f64);
            if d[k] == 0.0 {
                if o[k] < lo || o[k] > hi {
                    return None;
                }
                continue;
            }
            let (a, b) = ((lo - o[k]) * inv[k], (hi - o[k]) * inv[k]);
            let (t0, t1) = if a < b { (a, b) } else { (b, a) };
            if t0 > t_near {
                t_near = t0;
                near_axis = k;
            }
            t_far = t_far.min(t1);
        }
        let (t_start, axis_start) = if t_near > 0.0 {
            (t_near, Some(near_axis))
        } else {
            (0.0, None)
        };
        let t_end = t_far.min(t_max);
        if t_start >= t_end {
            return None;
        }
        let brick_lo = self.lo.map(|v| v.div_euclid(BRICK as i32));
        let brick_hi = self.hi.map(|v| (v - 1).div_euclid(BRICK as i32) + 1);
        let mut found = None;
        let b = BRICK as i32;
        walk(
            o,
            d,
            inv,
            (t_start, t_end),
            axis_start,
            (brick_lo, brick_hi),
            BRICK as f64,
            |brick| {
                let [bx, by, bz] = brick.cell;
                let bd = &self.brick_dims;
                if self.bricks[(bx + bd[0] * (by + bd[1] * bz)) as usize] == 0 {
                    return false;
                }
                let lo = [0, 1, 2].map(|k| (brick.cell[k] * b).max(self.lo[k]));
                let hi = [0, 1, 2].map(|k| (brick.cell[k] * b + b).min(self.hi[k]));
                walk(
                    o,
                    d,
                    inv,
                    (brick.t_in, brick.t_out),
                    brick.axis_in,
                    (lo, hi),
                    1.0,
                    |s| {
                        let [x, y, z] = s.cell.map(|c| c as u32);
                        if self.grid.get(x, y, z) == 0 {
                            return false;
                        }
                        found = match s.axis_in {
                            // Entering through the min face when going up the axis.
                            Some(k) if s.t_in > 0.0 => Some(GridHit {
                                t: s.t_in,
                                cell: s.cell,
                                face: if d[k] > 0.0 { k } else { k + 3 },
                            }),
                            // Starting inside a filled cell: its exit face, if before t_max.
                            _ if s.t_out < t_max && s.t_out > 0.0 => Some(GridHit {
                                t: s.t_out,
                                cell: s.cell,
                                face: if d[s.axis_out] > 0.0 {
                                    s.axis_out + 3
                                } else {
                                    s.axis_out
                                },
                            }),
                            _ => None,
                        };
                        true
                    },
                )
            },
        );
        found
    }

    /// Full interaction: the point put exactly on the face's plane (an integer in grid space,
    /// so that axis has no error; the others carry γ₃·|p|). With k the face's axis and
    /// (i, j) = (k + 1, k + 2) mod 3, a max face has (u, v) = (pᵢ − xᵢ, pⱼ − xⱼ) for the cell's
    /// corner x, ∂p/∂u = eᵢ, ∂p/∂v = eⱼ (so ∂p/∂u × ∂p/∂v = +e_k); a min face swaps i and j
    /// (normal −e_k): normals point out of the filled cell.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let face = hit.u as usize % 8;
        let (k, is_max) = (face % 3, face >= 3);
        let cell = self.hit_cell(hit).map(|c| c as f64);
        let mut g = o + self.offset + hit.t as f64 * d;
        for a in 0..3 {
            g[a] = g[a].clamp(cell[a], cell[a] + 1.0);
        }
        g[k] = cell[k] + if is_max { 1.0 } else { 0.0 };
        let (mut i, mut j) = ((k + 1) % 3, (k + 2) % 3);
        if !is_max {
            std::mem::swap(&mut i, &mut j);
        }
        let uv = Vec2::new((g[i] - cell[i]) as f32, (g[j] - cell[j]) as f32);
        // Grid and object space differ by a half-integer offset: p[k] stays exact.
        let p = (g - self.offset).as_vec3a();
        let mut p_err = gamma(3) * p.abs();
        p_err[k] = 0.0;
        SurfaceInteraction::from_object(
            &self.placement.to_world,
            p,
            p_err,
            uv,
            Vec3::AXES[i],
            Vec3::AXES[j],
            self.placement.flip_normal,
            -normalize(ray.d),
            hit.t,
        )
    }
}

/// Amanatides–Woo traversal of the cells of side `size` numbered [lo, hi) on each axis, for
/// `o + t·d` with t in `range` = [t0, t1]: each cell is visited in ray order until `visit`
/// returns true (then the walk returns true) or the ray leaves the range. On each axis the
/// next crossing is tₖ = (plane − oₖ)/dₖ, recomputed from the origin at every step rather than
/// accumulated (no drift). `axis0` is the axis through which the ray entered the range at t0
/// (its first cell on that axis is then the range's end, whatever the rounding says).
#[allow(clippy::too_many_arguments)]
#[inline]
fn walk(
    o: DVec3,
    d: DVec3,
    inv: DVec3,
    range: (f64, f64),
    axis0: Option<usize>,
    (lo, hi): ([i32; 3], [i32; 3]),
    size: f64,
    mut visit: impl FnMut(Step) -> bool,
) -> bool {
    let (t0, t1) = range;
    let p = o + t0 * d;
    let mut cell = [0i32; 3];
    let mut step = [0i32; 3];
    let mut t_next = [f64::INFINITY; 3];
    let plane = |c: i32, s: i32, k: usize| {
        let x = if s > 0 { c + 1 } else { c } as f64 * size;
        (x - o[k]) * inv[k]
    };
    for k in 0..3 {
        cell[k] = if axis0 == Some(k) {
            if d[k] > 0.0 { lo[k] } else { hi[k] - 1 }
        } else {
            ((p[k] / size)
                .floor()
                .clamp(i32::MIN as f64, i32::MAX as f64) as i32)
                .clamp(lo[k], hi[k] - 1)
        };
        if d[k] > 0.0 {
            step[k] = 1;
        } else if d[k] < 0.0 {
            step[k] = -1;
        }
        if step[k] != 0 {
            t_next[k] = plane(cell[k], step[k], k);
        }
    }
    let (mut t_in, mut axis_in) = (t0, axis0);
    loop {
        let k = if t_next[0] < t_next[1] {
            if t_next[0] < t_next[2] { 0 } else { 2 }
        } else if t_next[1] < t_next[2] {
            1
        } else {
            2
        };
        let step_k = Step {
            cell,
            t_in,
            axis_in,
            t_out: t_next[k].min(t1),
            axis_out: k,
        };
        if visit(step_k) {
            return true;
        }
        if t_next[k] >= t1 {
            return false;
        }
        cell[k] += step[k];
        if cell[k] < lo[k] || cell[k] >= hi[k] {
            return false;
        }
        t_in = t_next[k];
        axis_in = Some(k);
        t_next[k] = plane(cell[k], step[k], k);
    }
}

/// A voxel grid as a scene gives it (lancer's `voxels`), shared by its copies.
impl GeometryKind for Arc<VoxelGrid> {
    type Prim = Box<Voxels>;

    fn pbrt_name(&self) -> &'static str {
        "voxels"
    }

    /// Its constructor checks its size; an empty grid is valid (and makes no primitive).
    fn validate(&self) -> Result<(), RuleError> {
        Ok(())
    }

    fn emitter_refusal(&self) -> Option<&'static str> {
        Some(
            "a \"voxels\" shape cannot be an area light (AttributeBegin/AttributeEnd around \
             the AreaLightSource keeps it from the voxels)",
        )
    }

    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<Voxels>>,
    ) -> Result<(), String> {
        // An empty grid has nothing to hit: no primitive.
        if let Some(v) = Voxels::new(at.placement(), self.clone()) {
            out.extend([Box::new(v)]);
        }
        Ok(())
    }
}

/// A placed grid: no area (it cannot emit), its cells' palette colours as the hits' albedo.
impl ShapeKind for Voxels {
    fn bounds(&self) -> Bounds3 {
        Voxels::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Voxels::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Voxels::interaction(self, ray, hit)
    }

    fn area(&self) -> f32 {
        0.0
    }

    fn sample_area(&self, _: Vec2, _: &[TriangleMesh]) -> Option<ShapeSample> {
        None
    }

    #[inline]
    fn hit_albedo(&self, hit: &ShapeHit) -> Option<Rgb> {
        Some(Voxels::hit_albedo(self, hit))
    }

    /// The cells (a byte each, shared by instances of one grid but counted per instance) and
    /// the bricks.
    fn held_bytes(&self, _: &mut HashSet<usize>) -> HeldBytes {
        HeldBytes {
            primitive: self.heap_bytes(),
            meshes: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::testing::{assert_near, identity};

    /// A 2 × 1 × 1 grid with only cell (0, 0, 0) filled (palette index 7). With the offset
    /// (nx/2, ny/2, 0) = (1, ½, 0) that cell is [−1, 0] × [−½, ½] × [0, 1] in object space.
    fn one_cell() -> Voxels {
        let mut palette = [Rgb::ZERO; 256];
        palette[7] = Rgb::new(0.1, 0.2, 0.3);
        let grid = VoxelGrid::new([2, 1, 1], vec![7, 0], palette).unwrap();
        Voxels::new(identity(), Arc::new(grid)).unwrap()
    }

    fn hit(v: &Voxels, ray: &Ray) -> (ShapeHit, SurfaceInteraction) {
        let h = v.intersect(ray).expect("a hit");
        (h, v.interaction(ray, &h))
    }

    #[test]
    fn bounds_cover_the_filled_cells_only() {
        let b = one_cell().object_bounds();
        assert_eq!(
            (b.min, b.max),
            (Vec3::new(-1.0, -0.5, 0.0), Vec3::new(0.0, 0.5, 1.0))
        );
    }

    #[test]
    fn faces_hit_from_each_side_with_outward_normals() {
        let v = one_cell();
        // From −x: the min-x face x = −1 at t = 4, normal −x; a min face of axis 0 has
        // (u, v) = (z − 0, y_grid − 0) = (½, ½).
        let (h, si) = hit(&v, &Ray::new(Vec3::new(-5.0, 0.0, 0.5), Vec3::X));
        assert_eq!(h.t, 4.0);
        assert_eq!(v.hit_cell(&h), [0, 0, 0]);
        assert_eq!(v.hit_albedo(&h), Rgb::new(0.1, 0.2, 0.3));
        assert_near(si.p, Vec3::new(-1.0, 0.0, 0.5), 0.0);
        assert_near(si.n, -Vec3::X, 0.0);
        assert!(
            (si.uv - Vec2::splat(0.5)).abs().max_element() < 1e-6,
            "uv {}",
            si.uv
        );
        // From +x: through the empty cell [0, 1] to the filled cell's max-x face x = 0, t = 5.
        let (h, si) = hit(&v, &Ray::new(Vec3::new(5.0, 0.0, 0.5), -Vec3::X));
        assert_eq!(h.t, 5.0);
        assert_near(si.n, Vec3::X, 0.0);
        // From above onto the top z = 1 at t = 4.
        let (h, si) = hit(&v, &Ray::new(Vec3::new(-0.5, 0.0, 5.0), -Vec3::Z));
        assert_eq!(h.t, 4.0);
        assert_near(si.n, Vec3::Z, 0.0);
    }

    #[test]
    fn empty_cells_and_outside_rays_miss() {
        let v = one_cell();
        // Straight down through the empty cell, and beside the grid.
        assert!(
            v.intersect(&Ray::new(Vec3::new(0.5, 0.0, 5.0), -Vec3::Z))
                .is_none()
        );
        assert!(
            v.intersect(&Ray::new(Vec3::new(-0.5, 2.0, 5.0), -Vec3::Z))
                .is_none()
        );
        // Stopping short of the face.
        let short = Ray {
            t_max: 3.9,
            ..Ray::new(Vec3::new(-5.0, 0.0, 0.5), Vec3::X)
        };
        assert!(v.intersect(&short).is_none());
    }

    #[test]
    fn grids_are_validated() {
        let pal = [Rgb::ZERO; 256];
        let err = VoxelGrid::new([2, 0, 1], vec![], pal).unwrap_err();
        assert_eq!(err, "voxel grid dimensions [2, 0, 1] must all be positive");
        let err = VoxelGrid::new([2, 2, 1], vec![1; 3], pal).unwrap_err();
        assert_eq!(err, "voxel grid 2×2×1 needs 4 cells, got 3");
        // No filled cell: nothing to place.
        let empty = VoxelGrid::new([1, 1, 1], vec![0], pal).unwrap();
        assert!(Voxels::new(identity(), Arc::new(empty)).is_none());
    }
}
