//! Control and system elements (ADM-ELEMENTS §6–§12) as the analyses see them: first-order
//! states `x` with their laws, the matrices they read, and the plant input/output lists.
//!
//! State layout: every state element owns `size` consecutive entries from `offset` of one
//! vector `x` (and its rate `ẋ`) of [`Controls::count`] entries, in the order DIFFs, LSEs,
//! TFSISOs (definition order within each kind). The solver appends these after the 6
//! columns of every part.
//!
//! Laws (each state element's residual `r(x, ẋ, q, v, t) = 0`):
//! - DIFF explicit: `r = ẏ − f(…)`; IMPLICIT: `r = f(…, ẏ)` (ADM-ELEMENTS §6).
//! - LSE and TFSISO: `r = ẋ − (A x + B u)`, `u` the values of the U array's VARIABLEs, and the
//!   outputs `y = C x + D u` (the Y array, read by `ARYVAL`). A TFSISO is kept as the LSE of
//!   its observable canonical realisation ([`Linear::transfer_function`]).

use crate::bodies::Origin;
use linkage_adm::{Function, Located, Span};

/// A dense matrix, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct DenseMatrix {
    pub rows: usize,
    pub columns: usize,
    /// `values[i·columns + j]` is entry (i, j), 0-based.
    pub values: Vec<f64>,
}

impl DenseMatrix {
    /// A `rows × columns` matrix of zeros.
    pub fn zeros(rows: usize, columns: usize) -> DenseMatrix {
        DenseMatrix {
            rows,
            columns,
            values: vec![0.0; rows * columns],
        }
    }

    /// Entry (i, j), 0-based.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.values[i * self.columns + j]
    }

    /// Sets entry (i, j), 0-based.
    pub fn set(&mut self, i: usize, j: usize, x: f64) {
        self.values[i * self.columns + j] = x;
    }
}

/// `MATRIX/id`, with its values (a FILE's read when the model was built).
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix {
    pub origin: Origin,
    pub matrix: DenseMatrix,
}

/// A linear state law `ẋ = A x + B u`, `y = C x + D u` (LSE, TFSISO).
#[derive(Clone, Debug, PartialEq)]
pub struct Linear {
    /// n × n.
    pub a: DenseMatrix,
    /// n × (number of inputs); zero columns without U.
    pub b: DenseMatrix,
    /// (number of outputs) × n; zero rows without Y.
    pub c: DenseMatrix,
    /// outputs × inputs.
    pub d: DenseMatrix,
    /// The U array's VARIABLEs (indices into [`crate::Model::variables`]).
    pub inputs: Vec<usize>,
}

impl Linear {
    /// The observable canonical realisation of
    /// `H(s) = (b₀ + b₁s + … + b_m s^m)/(a₀ + a₁s + … + a_k s^k)`
    /// (ascending powers, m ≤ k, a_k ≠ 0), ADM-ELEMENTS §9: with `αᵢ = aᵢ/a_k`,
    /// `βᵢ = bᵢ/a_k`, `q = β_k` (the feed-through, 0 when m < k):
    /// `ẋ₁ = −α₀ x_k + (β₀ − α₀ q) u`, `ẋᵢ = xᵢ₋₁ − αᵢ₋₁ x_k + (βᵢ₋₁ − αᵢ₋₁ q) u`,
    /// `y = x_k + q u`, so that `C (sI − A)⁻¹ B + D = H(s)`. `None` when the denominator's
    /// last coefficient is 0 or the numerator has more coefficients than the denominator.
    pub fn transfer_function(
        numerator: &[f64],
        denominator: &[f64],
        input: usize,
    ) -> Option<Linear> {
        let k = denominator.len().checked_sub(1)?;
        let ak = *denominator.last()?;
        if ak == 0.0 || numerator.len() > denominator.len() {
            return None;
        }
        let alpha: Vec<f64> = denominator.iter().map(|a| a / ak).collect();
        let beta = |i: usize| numerator.get(i).map_or(0.0, |b| b / ak);
        let q = beta(k);
        let mut a = DenseMatrix::zeros(k, k);
        let mut b = DenseMatrix::zeros(k, 1);
        let mut c = DenseMatrix::zeros(1, k);
        for (i, alpha_i) in alpha.iter().enumerate().take(k) {
            if i > 0 {
                a.set(i, i - 1, 1.0);
            }
            a.set(i, k - 1, -alpha_i);
            b.set(i, 0, beta(i) - alpha_i * q);
        }
        if k > 0 {
            c.set(0, k - 1, 1.0);
        }
        let mut d = DenseMatrix::zeros(1, 1);
        d.set(0, 0, q);
        Some(Linear {
            a,
            b,
            c,
            d,
            inputs: vec![input],
        })
    }
}

/// The law of a state element.
#[derive(Clone, Debug, PartialEq)]
pub enum StateLaw {
    /// `DIFF`: explicit `ẏ = f` or IMPLICIT `0 = f(…, ẏ)`.
    Diff {
        function: Located<Function>,
        implicit: bool,
    },
    /// `LSE` or `TFSISO`.
    Linear(Box<Linear>),
}

/// A DIFF, LSE or TFSISO: its states `x[offset..offset + size]`.
#[derive(Clone, Debug, PartialEq)]
pub struct StateElement {
    pub origin: Origin,
    pub law: StateLaw,
    pub offset: usize,
    pub size: usize,
    /// Initial values of the states (DIFF IC, the LSE's IC array; 0 otherwise).
    pub initial: Vec<f64>,
    /// A first guess of the initial rates (DIFF `IC = y0, ẏ0`; 0 otherwise).
    pub initial_rate: Vec<f64>,
    /// `STATIC_HOLD`: statics keeps the states at their values instead of solving `ẋ = 0`.
    pub static_hold: bool,
    /// The X array (`ARYVAL` reads the states through it).
    pub x_array: Option<u64>,
    /// The Y array (`ARYVAL` reads the outputs `C x + D u` through it).
    pub y_array: Option<u64>,
}

/// `PINPUT/id` or `POUTPUT/id`: VARIABLEs (indices into [`crate::Model::variables`]) in order.
#[derive(Clone, Debug, PartialEq)]
pub struct PlantList {
    pub origin: Origin,
    pub variables: Vec<usize>,
}

/// Every control and system element of a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Controls {
    pub states: Vec<StateElement>,
    /// Number of states (the sum of the elements' sizes).
    pub count: usize,
    pub matrices: Vec<Matrix>,
    pub pinputs: Vec<PlantList>,
    pub poutputs: Vec<PlantList>,
}

impl Controls {
    /// The initial states and the guesses of their rates, `count` each.
    pub fn initial(&self) -> (Vec<f64>, Vec<f64>) {
        let mut x = vec![0.0; self.count];
        let mut xd = vec![0.0; self.count];
        for e in &self.states {
            x[e.offset..e.offset + e.size].copy_from_slice(&e.initial);
            xd[e.offset..e.offset + e.size].copy_from_slice(&e.initial_rate);
        }
        (x, xd)
    }

    /// The element owning state `i` and the state's place within it.
    pub fn owner(&self, i: usize) -> Option<(&StateElement, usize)> {
        self.states
            .iter()
            .find(|e| (e.offset..e.offset + e.size).contains(&i))
            .map(|e| (e, i - e.offset))
    }

    /// Whether state `i` is held in statics (its element has STATIC_HOLD).
    pub fn held(&self, i: usize) -> bool {
        self.owner(i).is_some_and(|(e, _)| e.static_hold)
    }

    /// `DIFF_3` for a DIFF, `LSE_1 x(2)` for the second state of an LSE: how reports name
    /// state `i`.
    pub fn state_name(&self, i: usize) -> String {
        match self.owner(i) {
            Some((e, _)) if e.size == 1 => e.origin.name.clone(),
            Some((e, k)) => format!("{} x({})", e.origin.name, k + 1),
            None => format!("state {i}"),
        }
    }
}

/// Where a MATRIX's FILE is: `name` relative to the dataset's folder.
pub fn matrix_file_path(dataset_file: &str, name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(dataset_file)
        .parent()
        .unwrap_or(std::path::Path::new(""));
    dir.join(name)
}

/// A matrix file that could not be read: what and where.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixFileError {
    pub span: Span,
    pub message: String,
}
