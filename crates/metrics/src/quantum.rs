//! Conduit lengths that are whole multiples of one quantum, so that every distance sum is exact.
//!
//! A positive float is `m 2^k` with m an odd integer. When the lengths of a graph, written in
//! units of the smallest such 2^k, are integers whose total times the node count stays below
//! 2^53, every partial sum of lengths along a path and every sum of distances is an integer
//! number of those units below 2^53: floating-point addition makes no rounding error, whatever
//! the order of the additions. Dijkstra's distances are then the exact integer distances times
//! the quantum, and any exact integer algorithm (breadth-first search when all lengths are equal,
//! a bucket queue when they are small multiples of the quantum) gives the same bits as
//! Dijkstra's float sums. Grid mazes and surveyed networks on a regular grid are such graphs; the
//! lengths of real caves (square roots of coordinate differences) almost never are.

/// Lengths as integer multiples (`units`) of `quantum`, exact as defined in the module docs.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Quantized {
    pub(crate) quantum: f64,
    /// Each length divided by `quantum` (at least 1).
    pub(crate) units: Vec<u32>,
    /// The largest unit count.
    pub(crate) max_unit: u32,
}

/// Largest number of quanta in one length: a bucket queue steps through every multiple of the
/// quantum up to the farthest distance, so far-apart lengths make it scan empty buckets.
pub(crate) const MAX_UNIT: u32 = 64;

/// The quantized form of `lengths` when all sums of distances between `n_nodes` nodes are exact
/// (module docs) and no length exceeds [`MAX_UNIT`] quanta; None otherwise (or if a length is
/// zero, negative or not finite).
pub(crate) fn quantize(lengths: &[f64], n_nodes: usize) -> Option<Quantized> {
    let dyadic: Vec<(u64, i32)> =
        lengths.iter().map(|&l| odd_times_power_of_two(l)).collect::<Option<_>>()?;
    let k_min = dyadic.iter().map(|&(_, k)| k).min()?;
    let whole: Vec<u64> = dyadic
        .iter()
        .map(|&(m, k)| {
            let shift = u32::try_from(k - k_min).ok().filter(|&s| s < 53)?;
            Some(m << shift).filter(|&w| w < 1 << 53)
        })
        .collect::<Option<_>>()?;
    let total = whole.iter().try_fold(0u64, |sum, &w| sum.checked_add(w))?;
    if u128::from(total) * n_nodes.max(1) as u128 >= 1 << 53 {
        return None;
    }
    let divisor = whole.iter().fold(0, |g, &w| gcd(g, w));
    let units: Vec<u32> = whole.iter().map(|&w| u32::try_from(w / divisor).ok()).collect::<Option<_>>()?;
    let max_unit = units.iter().copied().max()?;
    let quantum = lengths[0] / f64::from(units[0]);
    let exact = quantum.is_normal() && lengths.iter().zip(&units).all(|(&l, &u)| f64::from(u) * quantum == l);
    (max_unit <= MAX_UNIT && exact).then_some(Quantized { quantum, units, max_unit })
}

/// `(m, k)` with `l = m 2^k` and m odd, for a positive finite `l`.
fn odd_times_power_of_two(l: f64) -> Option<(u64, i32)> {
    if !(l > 0.0 && l.is_finite()) {
        return None;
    }
    let bits = l.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1 << 52) - 1);
    let (mantissa, exponent) =
        if biased == 0 { (fraction, -1074) } else { (fraction | 1 << 52, biased - 1075) };
    let zeros = mantissa.trailing_zeros();
    Some((mantissa >> zeros, exponent + zeros as i32))
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_lengths_are_units_of_their_common_divisor() {
        let q = quantize(&[10.0, 20.0, 10.0], 1000).expect("whole lengths");
        assert_eq!((q.quantum, q.units, q.max_unit), (10.0, vec![1, 2, 1], 2));
        let q = quantize(&[0.25, 0.75], 10).expect("dyadic lengths");
        assert_eq!((q.quantum, q.units), (0.25, vec![1, 3]));
    }

    #[test]
    fn inexact_or_far_apart_lengths_are_refused() {
        // 0.1 is not a short dyadic fraction of 0.3's quantum: their units exceed 2^53 or 64.
        assert_eq!(quantize(&[0.1, 0.3], 10), None);
        assert_eq!(quantize(&[2.0_f64.sqrt(), 1.0], 10), None);
        assert_eq!(quantize(&[1.0, 65.0], 10), None);
        assert_eq!(quantize(&[1.0, 0.0], 10), None);
        assert_eq!(quantize(&[1.0, f64::NAN], 10), None);
        // Exact for a few nodes, not once the distance sums could reach 2^53 units.
        assert!(quantize(&[1.0; 4], 1 << 50).is_some());
        assert_eq!(quantize(&[1.0; 4], 1 << 51), None);
        assert_eq!(quantize(&[], 10), None);
    }
}
