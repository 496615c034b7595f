//! k-nearest-neighbour search over the samples, in parallel, with a deterministic result.

use std::num::NonZero;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

/// For every point, its `k` nearest other points as (index, distance), nearest first, ties broken
/// by index; neighbours farther than `max_length` are left out. Results do not depend on the
/// number of threads.
pub fn neighbours(points: &[[f64; 3]], k: usize, max_length: Option<f64>) -> Vec<Vec<(u32, f64)>> {
    if points.len() < 2 || k == 0 {
        return vec![Vec::new(); points.len()];
    }
    // f32 coordinates relative to the first point keep millimetre precision over kilometres.
    let origin = points[0];
    let local: Vec<[f32; 3]> = points
        .iter()
        .map(|p| [(p[0] - origin[0]) as f32, (p[1] - origin[1]) as f32, (p[2] - origin[2]) as f32])
        .collect();
    let tree = ImmutableKdTree::new_from_slice(&local).expect("a non-empty point set builds a tree");
    let wanted = NonZero::new((k + 1).min(points.len())).expect("k + 1 > 0");
    let max2 = max_length.map(|l| l * l).unwrap_or(f64::INFINITY);
    (0..points.len())
        .into_par_iter()
        .map(|i| {
            let found = tree.query(&local[i]).nearest_n::<SquaredEuclidean<f32>>(wanted).execute();
            let mut list: Vec<(u32, f64)> = found
                .iter()
                .map(|n| n.item as usize)
                .filter(|&j| j != i)
                .map(|j| (j as u32, distance2(&points[i], &points[j])))
                .filter(|&(_, d2)| d2 <= max2)
                .collect();
            list.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            list.truncate(k);
            list.into_iter().map(|(j, d2)| (j, d2.sqrt())).collect()
        })
        .collect()
}

fn distance2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_brute_force() {
        let mut state = 12345u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 100.0
        };
        let points: Vec<[f64; 3]> = (0..300).map(|_| [next(), next(), next()]).collect();
        let got = neighbours(&points, 7, Some(30.0));
        for (i, list) in got.iter().enumerate() {
            let mut all: Vec<(u32, f64)> = (0..points.len())
                .filter(|&j| j != i)
                .map(|j| (j as u32, distance2(&points[i], &points[j]).sqrt()))
                .collect();
            all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            let expected: Vec<u32> = all.iter().take(7).filter(|n| n.1 <= 30.0).map(|n| n.0).collect();
            let ids: Vec<u32> = list.iter().map(|n| n.0).collect();
            assert_eq!(ids, expected, "node {i}");
        }
    }
}
