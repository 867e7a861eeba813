//! The runs of a sweep, numbered stably: run `i` has the same values whichever machine, shard
//! or thread computes it.
//!
//! Numbering: `i = s · P + c`, with `s` the sample (0 without `[sampling]`), `P` the product
//! of the value lists' lengths and `c` the position in their Cartesian product in table
//! order, the last `[[vary]]` table varying fastest. The value drawn for sample `s` from the
//! distribution of table `t` depends only on (seed, s, t): SplitMix64 (Steele, Lea and
//! Flood, OOPSLA 2014) as a counter-based generator, normals by Box–Muller.

use super::spec::{Distribution, Spec, Values};

/// SplitMix64's output function applied to `z` (a bijection of 64-bit words).
fn mix(z: u64) -> u64 {
    let mut z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The `k`-th uniform number in [0, 1) of stream (seed, sample, table).
fn uniform(seed: u64, sample: u64, table: u64, k: u64) -> f64 {
    let word = mix(mix(mix(seed) ^ sample) ^ (table << 8 | k));
    (word >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The value of sample `sample` drawn from `d` for table `table`.
pub fn draw(d: &Distribution, seed: u64, sample: u64, table: u64) -> f64 {
    match *d {
        Distribution::Uniform { low, high } => low + (high - low) * uniform(seed, sample, table, 0),
        Distribution::Normal { mean, sd } => {
            // u1 in (0, 1] so that ln(u1) is finite.
            let u1 = 1.0 - uniform(seed, sample, table, 0);
            let u2 = uniform(seed, sample, table, 1);
            mean + sd * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        }
    }
}

impl Spec {
    /// The varied values of run `index` (one per `[[vary]]` table, in table order).
    pub fn values(&self, index: usize) -> Vec<f64> {
        let combinations: usize = self
            .vary
            .iter()
            .map(|v| match &v.values {
                Values::List(l) => l.len(),
                Values::Drawn(_) => 1,
            })
            .product();
        let sample = (index / combinations) as u64;
        let mut rest = index % combinations;
        let mut out = vec![0.0; self.vary.len()];
        for (t, v) in self.vary.iter().enumerate().rev() {
            out[t] = match &v.values {
                Values::List(l) => {
                    let x = l[rest % l.len()];
                    rest /= l.len();
                    x
                }
                Values::Drawn(d) => draw(d, self.sampling.map_or(0, |s| s.seed), sample, t as u64),
            };
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn spec(text: &str) -> Spec {
        Spec::parse("s.toml", text, Path::new("")).expect("valid spec")
    }

    #[test]
    fn cartesian_product_numbers_the_last_table_fastest() {
        let s = spec(
            "model = 'm.adm'\n[analysis]\nkind = 'verify'\n\
             [[vary]]\nstatement = 'A/1'\nargument = 'K'\nvalues = [1.0, 2.0]\n\
             [[vary]]\nstatement = 'B/1'\nargument = 'C'\nrange = { start = 10.0, stop = 30.0, count = 3 }\n",
        );
        assert_eq!(s.run_count(), Some(6));
        let all: Vec<Vec<f64>> = (0..6).map(|i| s.values(i)).collect();
        assert_eq!(
            all,
            vec![
                vec![1.0, 10.0],
                vec![1.0, 20.0],
                vec![1.0, 30.0],
                vec![2.0, 10.0],
                vec![2.0, 20.0],
                vec![2.0, 30.0]
            ]
        );
    }

    #[test]
    fn samples_depend_only_on_seed_sample_and_table() {
        let text = "model = 'm.adm'\n[analysis]\nkind = 'verify'\n[sampling]\ncount = 4000\nseed = 11\n\
                    [[vary]]\nstatement = 'A/1'\nargument = 'K'\ndistribution = { kind = 'normal', mean = 5.0, sd = 2.0 }\n\
                    [[vary]]\nstatement = 'B/1'\nargument = 'C'\ndistribution = { kind = 'uniform', low = -1.0, high = 3.0 }\n";
        let s = spec(text);
        assert_eq!(s.run_count(), Some(4000));
        // The same run gives the same values, whoever asks.
        assert_eq!(s.values(1234), spec(text).values(1234));
        let n = 4000.0;
        let xs: Vec<f64> = (0..4000).map(|i| s.values(i)[0]).collect();
        let mean = xs.iter().sum::<f64>() / n;
        let sd = (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        // Standard error of the mean 2/sqrt(4000) = 0.032: within 4 of them; the sample sd
        // within 5 % of 2.
        assert!((mean - 5.0).abs() < 0.13, "mean {mean}");
        assert!((sd - 2.0).abs() < 0.1, "sd {sd}");
        let us: Vec<f64> = (0..4000).map(|i| s.values(i)[1]).collect();
        assert!(us.iter().all(|u| (-1.0..3.0).contains(u)));
        // Uniform on [-1, 3): mean 1, standard error 4/sqrt(12·4000) = 0.018.
        let umean = us.iter().sum::<f64>() / n;
        assert!((umean - 1.0).abs() < 0.08, "uniform mean {umean}");
        // Another seed draws other values.
        let other = spec(&text.replace("seed = 11", "seed = 12"));
        assert_ne!(other.values(0), s.values(0));
    }

    #[test]
    fn bad_specs_are_refused_with_the_table_named() {
        let base = "model = 'm.adm'\n[analysis]\nkind = 'verify'\n";
        let err = |extra: &str| {
            Spec::parse("s.toml", &format!("{base}{extra}"), Path::new(""))
                .expect_err("refused")
                .to_string()
        };
        assert!(err("").contains("at least one [[vary]]"));
        let both = err("[[vary]]\nstatement = 'A/1'\nargument = 'K'\nvalues = [1.0]\nrange = { start = 1.0, stop = 2.0, count = 2 }\n");
        assert!(
            both.contains("table 1 (A/1, K)") && both.contains("exactly one"),
            "{both}"
        );
        let unseeded = err("[[vary]]\nstatement = 'A/1'\nargument = 'K'\ndistribution = { kind = 'uniform', low = 0.0, high = 1.0 }\n");
        assert!(unseeded.contains("[sampling]"), "{unseeded}");
        let typo = err("[[vary]]\nstatment = 'A/1'\n");
        assert!(typo.contains("line") && typo.contains("statment"), "{typo}");
    }
}
