//! Regular 3D grids of integer codes as the voxel readers ([`crate::vti`], [`crate::npy`])
//! return them: where the voxels are and each voxel's code, before any code means a rock.

/// Where the voxels are: boxes of `spacing` centred on first_centre + (i, j, k)·spacing.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Lattice {
    /// Centre of voxel [0, 0, 0].
    pub first_centre: [f64; 3],
    pub spacing: [f64; 3],
    pub size: [usize; 3],
}

/// A regular 3D grid of integer codes as a reader returns it, x fastest, then y, then z.
#[derive(Debug, Clone, PartialEq)]
pub struct Voxels {
    pub lattice: Lattice,
    pub codes: Vec<i32>,
}

impl Lattice {
    /// The voxel containing `p` (clamped to the grid).
    pub fn index(&self, p: [f64; 3]) -> usize {
        let at = |a: usize| {
            let t = ((p[a] - self.first_centre[a]) / self.spacing[a] + 0.5).floor();
            t.clamp(0.0, (self.size[a] - 1) as f64) as usize
        };
        (at(2) * self.size[1] + at(1)) * self.size[0] + at(0)
    }

    /// `[low, high]` of the voxels' boxes along each axis.
    pub fn bounds(&self) -> [[f64; 2]; 3] {
        std::array::from_fn(|a| {
            let half = 0.5 * self.spacing[a];
            [
                self.first_centre[a] - half,
                self.first_centre[a] + (self.size[a] - 1) as f64 * self.spacing[a] + half,
            ]
        })
    }
}
