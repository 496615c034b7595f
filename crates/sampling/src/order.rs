//! The samples' storage order: key points first, then every other sample along a Morton
//! (Z-order) curve through the domain.
//!
//! The sampler appends its samples colour by colour (phase groups), so two neighbours in space
//! are usually far apart in the arrays: every later stage that walks from a sample to its
//! neighbours (the cost graph's edge costs, the skeleton's searches over the graph's rows and
//! costs, each indexed by sample) then reads a different cache line, often a different page,
//! per neighbour. Along a space-filling curve a neighbourhood is a few runs of consecutive
//! indices. The order changes no position and no tag, only which index a sample has.

use rayon::prelude::*;

/// Bits per axis of the curve's key: 2²¹ steps per axis, below a millimetre on a 1 km domain.
const BITS: u32 = 21;

/// The permutation that stores `positions[..fixed]` first as they are, then the others in
/// Morton order of their position in the box [lo, hi] (ties by original index, so the order is
/// a function of the positions alone).
pub fn morton_permutation(positions: &[[f64; 3]], fixed: usize, (lo, hi): ([f64; 3], [f64; 3])) -> Vec<u32> {
    let steps = f64::from((1u32 << BITS) - 1);
    let cell = |p: &[f64; 3], axis: usize| {
        let span = (hi[axis] - lo[axis]).max(f64::MIN_POSITIVE);
        (((p[axis] - lo[axis]) / span).clamp(0.0, 1.0) * steps) as u64
    };
    let mut keyed: Vec<(u64, u32)> = positions[fixed..]
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            (spread(cell(p, 0)) | spread(cell(p, 1)) << 1 | spread(cell(p, 2)) << 2, (fixed + i) as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    (0..fixed as u32).chain(keyed.into_iter().map(|(_, i)| i)).collect()
}

/// Spreads the 21 low bits of `x` to every third bit of a u64.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_puts_each_bit_three_apart() {
        for bit in 0..BITS {
            assert_eq!(spread(1 << bit), 1 << (3 * bit), "bit {bit}");
        }
        assert_eq!(spread(u64::MAX), 0x1249_2492_4924_9249);
    }

    #[test]
    fn fixed_samples_stay_first_and_the_rest_follow_the_curve() {
        let box_ = ([0.0; 3], [8.0; 3]);
        // Two key points, then four samples in a scrambled order.
        let positions = [
            [7.0, 7.0, 7.0],
            [0.0, 0.0, 0.0],
            [8.0, 8.0, 8.0],
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
        ];
        let order = morton_permutation(&positions, 2, box_);
        assert_eq!(order, [0, 1, 3, 4, 5, 2]);
    }
}
