//! CMA-ES (Hansen 2016, "The CMA Evolution Strategy: A Tutorial", arXiv:1604.00772): a
//! derivative-free minimiser for a few noisy, non-separable parameters, with an ask-and-tell
//! interface so that the caller evaluates a whole generation in parallel, logs every candidate
//! and stops on its own budget.
//!
//! The search runs in the unit cube of the box: coordinate i of a point is
//! (value − min) / (max − min). Candidates outside [0, 1] are folded back by reflection
//! ([`reflect`]), which keeps the search distribution continuous at the bounds (Hansen's
//! boundary handling for box constraints). Defaults are the tutorial's (Table 1): λ = 4 + ⌊3 ln n⌋,
//! μ = ⌊λ/2⌋ log-linear positive weights, cumulation and learning rates from n and μ_eff,
//! rank-one and rank-μ updates of C, cumulative step-size adaptation.
//!
//! Randomness comes from one ChaCha8 stream ([`Random`]) through Box–Muller, and C is
//! diagonalised by cyclic Jacobi rotations in a fixed order: the same seed gives the same
//! candidates on every machine, whatever the number of threads.

use karst_scene::rng::Random;

use super::optimiser::{Optimiser, Start};

/// The state of the search.
pub struct Cmaes {
    n: usize,
    lambda: usize,
    weights: Vec<f64>,
    mu_eff: f64,
    c_sigma: f64,
    d_sigma: f64,
    c_c: f64,
    c_1: f64,
    c_mu: f64,
    /// E‖N(0, I)‖.
    chi_n: f64,
    mean: Vec<f64>,
    sigma: f64,
    /// Covariance, row-major n × n.
    c: Vec<f64>,
    /// Eigenvectors of C (columns, row-major) and the square roots of its eigenvalues.
    b: Vec<f64>,
    d: Vec<f64>,
    p_sigma: Vec<f64>,
    p_c: Vec<f64>,
    generation: usize,
    random: Random,
    /// The steps y = B D z of the last generation drawn (its points are m + σ y).
    steps: Vec<Vec<f64>>,
}

impl Cmaes {
    /// A search from `mean` (unit-cube coordinates) with step size `sigma`, `lambda` candidates
    /// per generation (None: the default), drawing from `random`.
    pub fn new(mean: Vec<f64>, sigma: f64, lambda: Option<usize>, random: Random) -> Cmaes {
        let n = mean.len();
        let nf = n as f64;
        let lambda = lambda.unwrap_or(4 + (3.0 * nf.ln()).floor() as usize).max(2);
        let mu = lambda / 2;
        let raw: Vec<f64> = (1..=mu).map(|i| ((lambda as f64 + 1.0) / 2.0).ln() - (i as f64).ln()).collect();
        let total: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / total).collect();
        let mu_eff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let c_sigma = (mu_eff + 2.0) / (nf + mu_eff + 5.0);
        let d_sigma = 1.0 + 2.0 * (((mu_eff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + c_sigma;
        let c_c = (4.0 + mu_eff / nf) / (nf + 4.0 + 2.0 * mu_eff / nf);
        let c_1 = 2.0 / ((nf + 1.3).powi(2) + mu_eff);
        let c_mu = (1.0 - c_1).min(2.0 * (mu_eff - 2.0 + 1.0 / mu_eff) / ((nf + 2.0).powi(2) + mu_eff));
        let chi_n = nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf));
        Cmaes {
            n,
            lambda,
            weights,
            mu_eff,
            c_sigma,
            d_sigma,
            c_c,
            c_1,
            c_mu,
            chi_n,
            mean,
            sigma,
            c: identity(n),
            b: identity(n),
            d: vec![1.0; n],
            p_sigma: vec![0.0; n],
            p_c: vec![0.0; n],
            generation: 0,
            random,
            steps: Vec::new(),
        }
    }

    /// The search of a calibration's [`Start`].
    pub fn from_start(start: Start) -> Cmaes {
        Cmaes::new(start.mean, start.sigma, start.population, start.random)
    }
}

impl Optimiser for Cmaes {
    fn lambda(&self) -> usize {
        self.lambda
    }

    fn sigma(&self) -> f64 {
        self.sigma
    }

    fn ask(&mut self) -> Vec<Vec<f64>> {
        let n = self.n;
        let mut steps = Vec::with_capacity(self.lambda);
        let mut points = Vec::with_capacity(self.lambda);
        for _ in 0..self.lambda {
            let z: Vec<f64> = (0..n).map(|_| normal(&mut self.random)).collect();
            let y: Vec<f64> =
                (0..n).map(|i| (0..n).map(|j| self.b[i * n + j] * self.d[j] * z[j]).sum()).collect();
            points.push((0..n).map(|i| self.mean[i] + self.sigma * y[i]).collect());
            steps.push(y);
        }
        self.steps = steps;
        points
    }

    /// Updates the distribution from the generation's objective values (lower is better; ties
    /// go to the earlier candidate).
    fn tell(&mut self, values: &[f64]) {
        let n = self.n;
        let mut order: Vec<usize> = (0..values.len()).collect();
        order.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
        let best = &order[..self.weights.len()];
        let y_w: Vec<f64> = (0..n)
            .map(|i| best.iter().zip(&self.weights).map(|(&k, w)| w * self.steps[k][i]).sum())
            .collect();
        for (m, y) in self.mean.iter_mut().zip(&y_w) {
            *m += self.sigma * y;
        }
        // C^{-1/2} y_w = B D⁻¹ Bᵀ y_w.
        let bt_y: Vec<f64> = (0..n).map(|j| (0..n).map(|i| self.b[i * n + j] * y_w[i]).sum()).collect();
        let inv_sqrt_c_y: Vec<f64> =
            (0..n).map(|i| (0..n).map(|j| self.b[i * n + j] * bt_y[j] / self.d[j]).sum()).collect();
        let ps = (self.c_sigma * (2.0 - self.c_sigma) * self.mu_eff).sqrt();
        for (p, v) in self.p_sigma.iter_mut().zip(&inv_sqrt_c_y) {
            *p = (1.0 - self.c_sigma) * *p + ps * v;
        }
        self.generation += 1;
        let norm = self.p_sigma.iter().map(|v| v * v).sum::<f64>().sqrt();
        let decay = 1.0 - (1.0 - self.c_sigma).powi(2 * self.generation as i32);
        let h_sigma = norm / decay.sqrt() / self.chi_n < 1.4 + 2.0 / (n as f64 + 1.0);
        let pc = f64::from(u8::from(h_sigma)) * (self.c_c * (2.0 - self.c_c) * self.mu_eff).sqrt();
        for (p, y) in self.p_c.iter_mut().zip(&y_w) {
            *p = (1.0 - self.c_c) * *p + pc * y;
        }
        let lost = (1.0 - f64::from(u8::from(h_sigma))) * self.c_1 * self.c_c * (2.0 - self.c_c);
        let keep = 1.0 - self.c_1 - self.c_mu + lost;
        for i in 0..n {
            for j in 0..n {
                let rank_mu: f64 = best
                    .iter()
                    .zip(&self.weights)
                    .map(|(&k, w)| w * self.steps[k][i] * self.steps[k][j])
                    .sum();
                self.c[i * n + j] =
                    keep * self.c[i * n + j] + self.c_1 * self.p_c[i] * self.p_c[j] + self.c_mu * rank_mu;
            }
        }
        self.sigma *= ((self.c_sigma / self.d_sigma) * (norm / self.chi_n - 1.0)).exp();
        let (vectors, values) = jacobi(&self.c, n);
        self.b = vectors;
        self.d = values.iter().map(|v| v.max(1e-20).sqrt()).collect();
    }
}

/// x folded into [0, 1] by reflection at both bounds (period 2).
pub fn reflect(x: f64) -> f64 {
    let t = x.rem_euclid(2.0);
    if t > 1.0 { 2.0 - t } else { t }
}

/// A standard normal deviate (Box–Muller, the cosine branch).
fn normal(random: &mut Random) -> f64 {
    let u = 1.0 - random.uniform(); // (0, 1]: ln is finite
    let v = random.uniform();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

fn identity(n: usize) -> Vec<f64> {
    (0..n * n).map(|k| f64::from(u8::from(k / n == k % n))).collect()
}

/// Eigen-decomposition of the symmetric matrix `a` (n × n, row-major) by cyclic Jacobi
/// rotations: the eigenvectors as columns of a row-major matrix, and the eigenvalues.
fn jacobi(a: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut a = a.to_vec();
    let mut v = identity(n);
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i * n + j].powi(2))
            .sum();
        let scale: f64 = (0..n).map(|i| a[i * n + i].powi(2)).sum::<f64>().max(f64::MIN_POSITIVE);
        if off <= 1e-30 * scale {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
                for k in 0..n {
                    let (akp, akq) = (a[k * n + p], a[k * n + q]);
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[p * n + k], a[q * n + k]);
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let (vkp, vkq) = (v[k * n + p], v[k * n + q]);
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    ((v), (0..n).map(|i| a[i * n + i]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_diagonalises_a_symmetric_matrix() {
        let a = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 1.0];
        let (v, d) = jacobi(&a, 3);
        for k in 0..3 {
            // A v_k = d_k v_k.
            for i in 0..3 {
                let av: f64 = (0..3).map(|j| a[i * 3 + j] * v[j * 3 + k]).sum();
                assert!((av - d[k] * v[i * 3 + k]).abs() < 1e-10, "{av} vs {}", d[k] * v[i * 3 + k]);
            }
        }
    }

    #[test]
    fn reflection_folds_into_the_unit_interval() {
        assert_eq!(reflect(0.25), 0.25);
        assert_eq!(reflect(1.25), 0.75);
        assert_eq!(reflect(-0.25), 0.25);
        assert_eq!(reflect(2.5), 0.5);
    }

    /// A rotated, ill-conditioned ellipsoid: CMA-ES must learn the covariance to converge.
    #[test]
    fn minimises_a_rotated_ellipsoid_and_repeats_itself() {
        let f = |x: &[f64]| {
            let (u, v) = (x[0] + x[1] - 1.2, x[0] - x[1] + 0.1);
            u * u + 100.0 * v * v + (x[2] - 0.3).powi(2)
        };
        let search = |seed| {
            let mut es = Cmaes::new(vec![0.9, 0.1, 0.9], 0.3, None, Random::stream(seed, "test", "cmaes"));
            for _ in 0..150 {
                let points = es.ask();
                let values: Vec<f64> = points.iter().map(|p| f(p)).collect();
                es.tell(&values);
            }
            es.mean.clone()
        };
        let m = search(1);
        assert!(f(&m) < 1e-8, "f = {} at {m:?}", f(&m));
        assert_eq!(m, search(1), "same seed, same search");
    }
}
