//! The step table a dynamic simulation writes to the message file as it goes, in Adams'
//! layout (Adams Solver prints it under "Performing Dynamic Simulation"):
//!
//! ```text
//!    Simulation      Step       Corrector    Cumulative   Integration   Elapsed
//!       Time         Size       Iterations  Steps Taken      Order      time (s)
//!    ___________  ___________  ___________  ___________   ___________  ________
//!    0.00000E+00  0.00000E+00            0            0            0      0.00
//!    5.00000E-01  1.00000E-05        13085        50005            2      0.89
//! ```
//!
//! Contract:
//! - A row at the simulation's first output, then at the first output at or after each tenth
//!   of the simulated span (`t0 + k·(end − t0)/10`, k = 1…10), as Adams prints its table: at
//!   most eleven rows whatever the number of outputs.
//! - A row gives the output's time and the integrator's last accepted step before it: its
//!   size and order, the steps accepted and corrector iterations of this SIMULATE so far,
//!   and the wall-clock seconds since the simulation began. Adams' "Function Evaluations"
//!   column is linkage's corrector iterations (one residual evaluation each).
//! - A kinematic simulation takes no steps: it writes no table.

use linkage_solve::stages::dynamics::StepTaken;
use linkage_solve::tolerances::OUTPUT_HIT;
use std::time::Instant;

/// Rows over the simulated span (one more at the start).
const ROWS: usize = 10;

/// The step table of one SIMULATE.
pub struct StepTable {
    start: f64,
    end: f64,
    /// The next tenth of the span a row is due at (0: the first output).
    next: usize,
    /// The integrator's last step before the output that follows.
    taken: StepTaken,
    began: Instant,
    /// The header is written with the first row.
    headed: bool,
}

impl StepTable {
    /// The table of a simulation from `start` to `end`.
    pub fn new(start: f64, end: f64) -> StepTable {
        StepTable {
            start,
            end,
            next: 0,
            taken: StepTaken::default(),
            began: Instant::now(),
            headed: false,
        }
    }

    /// The integrator's last step before the next output.
    pub fn steps_so_far(&mut self, at: &StepTaken) {
        self.taken = *at;
    }

    /// The lines to write at the output at `time` (none when no row is due there): the
    /// header before the first row.
    pub fn at_output(&mut self, time: f64) -> Option<String> {
        let span = self.end - self.start;
        let reached =
            |k: usize| time >= self.start + span * k as f64 / ROWS as f64 - OUTPUT_HIT * span;
        if self.next > ROWS || !reached(self.next) {
            return None;
        }
        // Every tenth this output has reached or passed is served by its row.
        let mut next = self.next;
        while next <= ROWS && reached(next) {
            next += 1;
        }
        self.next = next;
        let mut lines = String::new();
        if !std::mem::replace(&mut self.headed, true) {
            lines.push_str(HEADER);
        }
        lines.push_str(&self.row(time));
        Some(lines)
    }

    fn row(&self, time: f64) -> String {
        use linkage_adm::num::sci;
        let t = &self.taken;
        format!(
            "   {:>11}  {:>11}  {:>11}  {:>11}   {:>11}  {:>8.2}\n",
            sci(time, 6),
            sci(t.step, 6),
            t.iterations,
            t.steps,
            t.order,
            self.began.elapsed().as_secs_f64()
        )
    }
}

const HEADER: &str = "\n   Simulation      Step       Corrector    Cumulative   Integration   Elapsed\n      Time         Size       Iterations  Steps Taken      Order      time (s)\n   ___________  ___________  ___________  ___________   ___________  ________\n";

#[cfg(test)]
mod tests {
    use super::*;

    fn step(time: f64, steps: usize) -> StepTaken {
        StepTaken {
            time,
            step: 0.01,
            order: 2,
            steps,
            rejected: 0,
            iterations: 3 * steps,
        }
    }

    #[test]
    fn a_row_at_the_start_and_at_each_tenth_of_the_span_whatever_the_outputs() {
        // 1000 outputs over 0…5 s: 11 rows, at 0, 0.5, …, 5.
        let mut table = StepTable::new(0.0, 5.0);
        let mut rows = Vec::new();
        for k in 0..=1000 {
            let t = k as f64 * 0.005;
            table.steps_so_far(&step(t, k));
            if let Some(lines) = table.at_output(t) {
                rows.push((t, lines));
            }
        }
        let times: Vec<f64> = rows.iter().map(|r| r.0).collect();
        assert_eq!(times.len(), 11, "{times:?}");
        for (k, t) in times.iter().enumerate() {
            assert!((t - 0.5 * k as f64).abs() < 1e-9, "{times:?}");
        }
        // The header once, before the first row.
        assert!(rows[0].1.contains("Cumulative"));
        assert!(rows[1..].iter().all(|r| !r.1.contains("Cumulative")));
        assert!(rows[10]
            .1
            .starts_with("   5.00000E+00  1.00000E-02         3000         1000             2"));
    }

    #[test]
    fn outputs_coarser_than_a_tenth_each_get_one_row() {
        // Outputs every 0.25 of a span of 1 from t0 = 2 (a command file's second SIMULATE).
        let mut table = StepTable::new(2.0, 3.0);
        let rows: Vec<f64> = (1..=4)
            .map(|k| 2.0 + 0.25 * k as f64)
            .filter(|t| table.at_output(*t).is_some())
            .collect();
        assert_eq!(rows, vec![2.25, 2.5, 2.75, 3.0]);
    }
}
