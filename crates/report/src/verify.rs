//! The verify report: Adams View "Verify Model" style text, and JSON.

use crate::units::{text_line, units_json, Angle, UnitsJson};
use linkage_adm::Diagnostic;
use linkage_model::Model;
use linkage_solve::constraints::system::RowUnit;
use linkage_solve::pipeline::verify::Verification;
use serde::Serialize;
use std::borrow::Cow;
use std::fmt::Write;
use std::sync::Arc;

/// An equation named the way engineers read it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct EquationRef {
    /// `JOINT/2`. (Shared: a large model's report names each element in many equations.)
    pub element: Arc<str>,
    /// `JOINT_2` (or the `adams_view_name`).
    pub name: Arc<str>,
    /// `Revolute Joint`.
    #[serde(rename = "type")]
    pub kind: Arc<str>,
    /// `Rotation Between Zi & Xj`.
    pub equation: &'static str,
    /// `Zi.Xj` (Adams Solver's short form).
    pub short: &'static str,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DependencyJson {
    #[serde(flatten)]
    pub equation: EquationRef,
    pub coefficient: f64,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RedundantJson {
    #[serde(flatten)]
    pub equation: EquationRef,
    pub depends_on: Vec<DependencyJson>,
    /// `true`/`false` at an assembled configuration, `null` when unknown.
    pub consistent: Option<bool>,
    /// Residual in `residual_unit` (`null` when it cannot be evaluated).
    pub residual: Option<f64>,
    pub residual_unit: &'static str,
    pub near_tie: bool,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MisalignedJson {
    #[serde(flatten)]
    pub equation: EquationRef,
    pub residual: f64,
    pub residual_unit: &'static str,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CountJson {
    #[serde(rename = "type")]
    pub kind: String,
    pub count: usize,
}

/// An FE_PART in the counts: the chapter's equivalent linear flexible body (fixed-boundary
/// normal modes + 6 constraint modes per node markers use + 6 rigid-body modes) and its true
/// nodal degrees of freedom.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FePartJson {
    pub name: String,
    pub nodes: usize,
    pub elements: usize,
    /// Labels of the nodes markers use (the Craig–Bampton boundary).
    pub marker_nodes: Vec<u64>,
    /// Normal modes asked for (20, or MSC_NLFE_MNFSWAP_EIGENVALUES).
    pub normal_modes_requested: usize,
    /// Normal modes available: at most the interior degrees of freedom.
    pub normal_modes: usize,
    pub constraint_modes: usize,
    pub rigid_body_modes: usize,
    /// normal + constraint + rigid-body modes: what the Gruebler count takes.
    pub gruebler_dof: usize,
    /// Degrees of freedom of the node bodies (what the DOF by rank uses).
    pub nodal_dof: usize,
    /// The fixed-boundary natural frequencies (cycles per time unit), lowest first.
    pub normal_frequencies: Vec<f64>,
}

/// A FLEX_BODY in the counts: its modes + 6 rigid coordinates.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FlexBodyJson {
    pub name: String,
    pub modes: usize,
    /// Nodes markers use (their equations tie them to the modal coordinates).
    pub marker_nodes: Vec<u64>,
    /// modes + 6: what the Gruebler count takes.
    pub gruebler_dof: usize,
    /// Natural frequency of each mode (cycles per time unit), in SELMOD order.
    pub frequencies: Vec<f64>,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MasslessJson {
    pub name: String,
    pub free_coordinates: Vec<&'static str>,
}

/// The JSON document of `linkage verify --format json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct VerifyJson {
    pub file: String,
    pub title: String,
    /// Residuals in degrees.
    pub units: UnitsJson,
    /// Statements left out on request (`--deactivate`).
    pub left_out: Vec<crate::coverage::LeftOutJson>,
    /// Every statement some later analysis refuses or runs without: not modelled, a USER
    /// subroutine, a missing external file, not used.
    pub not_run: Vec<crate::coverage::FindingJson>,
    /// The analyses that refuse this model (`ic`, `static`, `static --end`, `linear`,
    /// `simulate`).
    pub later_refused_by: Vec<&'static str>,
    /// Moving parts (point masses and FE nodes not included).
    pub moving_parts: usize,
    /// POINT_MASS elements (3 degrees of freedom each).
    pub point_masses: usize,
    /// FE_PARTs, each counted as Adams' equivalent linear flexible body.
    pub fe_parts: Vec<FePartJson>,
    /// FLEX_BODYs, each counted as its modes + 6.
    pub flex_bodies: Vec<FlexBodyJson>,
    pub constraint_counts: Vec<CountJson>,
    /// The equations of the constraint elements (the point masses' and cable nodes' held
    /// rotations not included): Gruebler = 6·parts + 3·point masses + Σ FE parts'
    /// `gruebler_dof` − equations.
    pub constraint_equations: usize,
    pub gruebler: i64,
    pub rank: usize,
    pub dof: i64,
    /// Whether every independent equation holds at the input configuration.
    pub assembled: bool,
    pub redundant: Vec<RedundantJson>,
    pub misaligned: Vec<MisalignedJson>,
    /// Misaligned elements whose rank analysis used their repaired (idealised) frames.
    pub analysed_as_repaired: Vec<String>,
    pub unconstrained_parts: Vec<String>,
    pub ungrounded_parts: Vec<String>,
    /// Massless parts whose motion the constraints do not determine (dynamics cannot run).
    pub massless_parts: Vec<String>,
    pub massless_free: Vec<MasslessJson>,
    /// Every part with zero mass.
    pub zero_mass_parts: Vec<String>,
    /// Independent equations whose rank decision was close to the tolerance.
    pub near_ties: Vec<EquationRef>,
    pub warnings: Vec<String>,
    pub errors: Vec<String>,
    /// For a model not assembled at its input configuration: DOF and redundancy at the
    /// configuration the assembly (`linkage ic`) reaches, which is what every analysis uses.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub after_assembly: Option<AfterAssemblyJson>,
    /// `--explain`: suggestions, determinate reactions, singular configuration, drivers.
    #[serde(flatten)]
    pub explain: Option<crate::explain::ExplainJson>,
}

/// DOF and redundancy at the assembled configuration (see [`after_assembly_json`]).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AfterAssemblyJson {
    /// Whether the displacement assembly converged (the counts are only given when it did).
    pub converged: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dof: Option<i64>,
    /// The redundant equations there, named as in `redundant`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub redundant: Option<Vec<EquationRef>>,
}

/// The counts of the assembled configuration `at` (the verification `linkage ic` runs after
/// its assembly), or only `converged: false` when the assembly did not converge.
pub fn after_assembly_json(model: &Model, converged: bool, at: &Verification) -> AfterAssemblyJson {
    AfterAssemblyJson {
        converged,
        dof: converged.then_some(at.dof),
        redundant: converged.then(|| {
            at.redundant
                .iter()
                .map(|r| equation_ref(model, at, r.row))
                .collect()
        }),
    }
}

fn unit_name(u: RowUnit) -> &'static str {
    match u {
        RowUnit::Length | RowUnit::Mixed => "length",
        RowUnit::Direction | RowUnit::Angle => "degrees",
    }
}

/// Names an equation (row) of the verification's system.
pub fn equation_ref(model: &Model, v: &Verification, row: usize) -> EquationRef {
    let r = &v.system.rows[row];
    let c = &model.constraints[r.element];
    EquationRef {
        element: c.origin.element().into(),
        name: c.origin.name.as_str().into(),
        kind: c.description().into(),
        equation: r.label,
        short: r.short,
    }
}

/// `(element, name, kind)` of one element, as in [`EquationRef`].
type ElementNames = (Arc<str>, Arc<str>, Arc<str>);

/// [`equation_ref`] with the names of each element (`JOINT/2`, `JOINT_2`, `Revolute Joint`)
/// formatted once: a chain of 10,000 loops names 220,000 equations of 30,000 elements.
struct EquationNames<'a> {
    model: &'a Model,
    v: &'a Verification,
    /// Per element: `(element, name, kind)` as in [`EquationRef`].
    elements: Vec<Option<ElementNames>>,
}

impl<'a> EquationNames<'a> {
    fn new(model: &'a Model, v: &'a Verification) -> Self {
        EquationNames {
            model,
            v,
            elements: vec![None; model.constraints.len()],
        }
    }

    fn get(&mut self, row: usize) -> EquationRef {
        let r = &self.v.system.rows[row];
        let model = self.model;
        let (element, name, kind) = self.elements[r.element].get_or_insert_with(|| {
            let c = &model.constraints[r.element];
            (
                c.origin.element().into(),
                c.origin.name.as_str().into(),
                c.description().into(),
            )
        });
        EquationRef {
            element: element.clone(),
            name: name.clone(),
            kind: kind.clone(),
            equation: r.label,
            short: r.short,
        }
    }
}

/// Builds the JSON document.
pub fn to_json(model: &Model, v: &Verification, warnings: &[Diagnostic]) -> VerifyJson {
    let part_name = |k: usize| model.parts[k].origin.name.clone();
    let mut names = EquationNames::new(model, v);
    let redundant = v
        .redundant
        .iter()
        .map(|r| RedundantJson {
            equation: names.get(r.row),
            depends_on: r
                .depends_on
                .iter()
                .map(|d| DependencyJson {
                    equation: names.get(d.row),
                    coefficient: d.coefficient,
                })
                .collect(),
            consistent: r.consistent,
            residual: r.residual,
            residual_unit: unit_name(v.system.rows[r.row].unit),
            near_tie: r.near_tie,
        })
        .collect();
    VerifyJson {
        file: model.file.to_string(),
        title: model.title.clone(),
        units: units_json(model, Angle::Degree, false),
        left_out: Vec::new(),
        not_run: Vec::new(),
        later_refused_by: Vec::new(),
        moving_parts: v.moving_parts - v.point_masses - v.fe_nodes - v.flex_parts,
        point_masses: v.point_masses,
        fe_parts: v
            .fe_parts
            .iter()
            .map(|m| FePartJson {
                name: model.fe_parts[m.fe].origin.name.clone(),
                nodes: m.nodes,
                elements: m.elements,
                marker_nodes: m.boundary_labels.clone(),
                normal_modes_requested: m.count.requested,
                normal_modes: m.count.normal_modes,
                constraint_modes: m.count.constraint_modes,
                rigid_body_modes: m.count.rigid_modes,
                gruebler_dof: m.count.total(),
                nodal_dof: m.nodal_dof,
                normal_frequencies: m.normal_frequencies.clone(),
            })
            .collect(),
        constraint_counts: v
            .counts
            .iter()
            .map(|(k, n)| CountJson {
                kind: k.clone(),
                count: *n,
            })
            .collect(),
        flex_bodies: model
            .flex_bodies
            .iter()
            .map(|b| FlexBodyJson {
                name: b.origin.name.clone(),
                modes: b.modes.len(),
                marker_nodes: b.nodes.iter().map(|n| n.id).collect(),
                gruebler_dof: b.gruebler_dof(),
                frequencies: b.modes.iter().map(|m| m.frequency).collect(),
            })
            .collect(),
        constraint_equations: v.rows - v.hold_rows - v.flex_rows,
        gruebler: v.gruebler,
        rank: v.rank,
        dof: v.dof,
        assembled: v.assembled,
        redundant,
        misaligned: v
            .misaligned
            .iter()
            .map(|m| MisalignedJson {
                equation: equation_ref(model, v, m.row),
                residual: m.residual,
                residual_unit: unit_name(v.system.rows[m.row].unit),
            })
            .collect(),
        analysed_as_repaired: v
            .idealized
            .iter()
            .map(|&e| model.constraints[e].origin.name.clone())
            .collect(),
        // An FE part is named by itself, not by the node that stands for it.
        unconstrained_parts: v
            .unconstrained_parts
            .iter()
            .map(|&k| match model.fe_node(k) {
                Some((f, _)) => model.fe_parts[f].origin.name.clone(),
                None => part_name(k),
            })
            .collect(),
        ungrounded_parts: v.ungrounded_parts.iter().map(|&k| part_name(k)).collect(),
        massless_parts: v.massless_free.iter().map(|f| part_name(f.part)).collect(),
        massless_free: v
            .massless_free
            .iter()
            .map(|f| MasslessJson {
                name: part_name(f.part),
                free_coordinates: f.coordinates.clone(),
            })
            .collect(),
        zero_mass_parts: v.massless_parts.iter().map(|&k| part_name(k)).collect(),
        near_ties: v
            .near_tie_admitted
            .iter()
            .map(|&r| equation_ref(model, v, r))
            .collect(),
        warnings: warnings.iter().map(|w| w.to_string()).collect(),
        errors: inconsistency(model, v).into_iter().collect(),
        after_assembly: None,
        explain: None,
    }
}

/// The verdict on redundant equations that do not hold with the others, in one line with what
/// to try (`None` when none is known to be inconsistent).
fn inconsistency(model: &Model, v: &Verification) -> Option<String> {
    let bad: Vec<String> = v
        .redundant
        .iter()
        .filter(|r| r.consistent == Some(false))
        .map(|r| {
            let e = equation_ref(model, v, r.row);
            let unit = unit_name(v.system.rows[r.row].unit);
            match r.residual {
                Some(x) => format!(
                    "{} of {} (residual {})",
                    e.equation,
                    e.name,
                    fmt_residual(x, unit)
                ),
                None => format!("{} of {}", e.equation, e.name),
            }
        })
        .collect();
    (!bad.is_empty()).then(|| {
        format!(
            "the model is inconsistent: redundant equation(s) cannot hold with the others: {}; \
             `linkage ic` shows what assembly repairs, `linkage verify --explain` proposes joints \
             without the redundancy",
            bad.join(", ")
        )
    })
}

/// Why the consistency of the redundant equations is unknown, in one line (`None` when the
/// model is assembled at the input configuration or has no redundant equation).
pub fn not_assembled_line(j: &VerifyJson) -> Option<String> {
    let unknown = j
        .redundant
        .iter()
        .filter(|r| r.consistent.is_none())
        .count();
    (!j.assembled).then(|| {
        let why = if unknown > 0 {
            format!(
                "; the consistency of the {unknown} redundant equation(s) is unknown until it is"
            )
        } else {
            String::new()
        };
        format!(
            "The model is not assembled at the input configuration (some independent equation, \
             a joint or a motion at its start value, does not hold){why}: run `linkage ic` to \
             assemble it."
        )
    })
}

fn plural(n: usize, one: &str) -> String {
    if n == 1 {
        one.to_string()
    } else if let Some(stem) = one.strip_suffix('y') {
        format!("{stem}ies")
    } else {
        format!("{one}s")
    }
}

fn fmt_residual(x: f64, unit: &str) -> String {
    match unit {
        "degrees" => format!("{x:.4} deg"),
        _ => crate::num::sci(x, 5),
    }
}

/// Human report in the spirit of Adams View's "Verify Model", ending with the run's verdict:
/// its errors, one `error: …` line each (none when the model verified).
pub fn to_text(j: &VerifyJson) -> String {
    let mut s = body_text(j);
    s.push_str(&error_lines(&j.errors));
    s
}

/// `error: …`, one line per error.
pub fn error_lines(errors: &[String]) -> String {
    errors.iter().map(|e| format!("error: {e}\n")).collect()
}

/// The report without its errors (for a caller that adds more sections before the verdict).
pub fn body_text(j: &VerifyJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "VERIFY MODEL: {}", j.title);
    let _ = writeln!(s, "  file: {}", j.file);
    let _ = writeln!(s, "{}", text_line(&j.units));
    s.push_str(&crate::coverage::left_out_text(&j.left_out));
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{:>5} Gruebler Count (approximate degrees of freedom)",
        j.gruebler
    );
    let _ = writeln!(
        s,
        "{:>5} Moving Parts (not including ground)",
        j.moving_parts
    );
    if j.point_masses > 0 {
        let _ = writeln!(
            s,
            "{:>5} Point Masses (3 degrees of freedom each)",
            j.point_masses
        );
    }
    if !j.fe_parts.is_empty() {
        let _ = writeln!(
            s,
            "{:>5} FE Parts (equivalent linear flexible bodies)",
            j.fe_parts.len()
        );
        for f in &j.fe_parts {
            let labels: Vec<String> = f.marker_nodes.iter().map(u64::to_string).collect();
            let _ = writeln!(
                s,
                "        {}: {} nodes; {} normal modes ({} requested) + {} constraint modes \
                 (marker nodes: {}) + {} rigid-body modes = {} in the Gruebler count; \
                 {} nodal degrees of freedom",
                f.name,
                f.nodes,
                f.normal_modes,
                f.normal_modes_requested,
                f.constraint_modes,
                if labels.is_empty() {
                    "none".to_string()
                } else {
                    labels.join(", ")
                },
                f.rigid_body_modes,
                f.gruebler_dof,
                f.nodal_dof
            );
            if let Some(first) = f.normal_frequencies.first() {
                let _ = writeln!(
                    s,
                    "        first fixed-boundary normal mode {} cycles per time unit",
                    linkage_adm::num::general(*first, 6)
                );
            }
        }
    }
    if !j.flex_bodies.is_empty() {
        let _ = writeln!(
            s,
            "{:>5} Flex Bodies (modes + 6 degrees of freedom each)",
            j.flex_bodies.len()
        );
        for f in &j.flex_bodies {
            let labels: Vec<String> = f.marker_nodes.iter().map(u64::to_string).collect();
            let _ = writeln!(
                s,
                "        {}: {} modes + 6 = {} in the Gruebler count; marker nodes: {}",
                f.name,
                f.modes,
                f.gruebler_dof,
                if labels.is_empty() {
                    "none".to_string()
                } else {
                    labels.join(", ")
                }
            );
        }
    }
    for c in &j.constraint_counts {
        let _ = writeln!(s, "{:>5} {}", c.count, plural(c.count, &c.kind));
    }
    let _ = writeln!(s, "{:>5} Constraint Equations", j.constraint_equations);
    let _ = writeln!(s);
    let _ = writeln!(s, "{:>5} Degrees of Freedom", j.dof);
    let _ = writeln!(s);
    match j.redundant.len() {
        0 => {
            let _ = writeln!(s, "There are no redundant constraint equations.");
        }
        n => {
            let _ = writeln!(
                s,
                "There {} {n} redundant constraint {}.",
                if n == 1 { "is" } else { "are" },
                plural(n, "equation")
            );
            let _ = writeln!(s);
            let left: Vec<String> = j
                .redundant
                .iter()
                .map(|r| format!("{} ({})", r.equation.name, r.equation.kind))
                .collect();
            let w = left
                .iter()
                .map(|l| l.len())
                .max()
                .unwrap_or(0)
                .max("This constraint:".len())
                + 3;
            let _ = writeln!(
                s,
                "   {:<w$}unnecessarily removes this DOF:",
                "This constraint:"
            );
            for (r, l) in j.redundant.iter().zip(&left) {
                let status: Cow<str> = match (r.consistent, r.residual) {
                    (Some(true), _) => "consistent".into(),
                    (Some(false), Some(x)) => format!(
                        "INCONSISTENT (residual {})",
                        fmt_residual(x, r.residual_unit)
                    )
                    .into(),
                    (Some(false), None) => "INCONSISTENT".into(),
                    (None, Some(x)) => format!(
                        "consistency unknown (residual {})",
                        fmt_residual(x, r.residual_unit)
                    )
                    .into(),
                    (None, None) => "consistency unknown".into(),
                };
                let tie = if r.near_tie {
                    ", near-tie rank decision"
                } else {
                    ""
                };
                // Pushed piece by piece: a large model has tens of thousands of these lines.
                s.push_str("   ");
                push_padded(&mut s, l, w);
                push_padded(&mut s, r.equation.equation, 36);
                s.push(' ');
                s.push_str(&status);
                s.push_str(tie);
                s.push('\n');
                if !r.depends_on.is_empty() {
                    push_padded(&mut s, "", w + 3);
                    s.push_str("  = ");
                    for (k, d) in r.depends_on.iter().take(6).enumerate() {
                        if k > 0 {
                            s.push_str(", ");
                        }
                        push_coefficient(&mut s, d.coefficient);
                        s.push(' ');
                        s.push_str(&d.equation.name);
                        s.push(' ');
                        s.push_str(d.equation.short);
                    }
                    if r.depends_on.len() > 6 {
                        let _ = write!(s, " … ({} more)", r.depends_on.len() - 6);
                    }
                    s.push('\n');
                }
            }
        }
    }
    if !j.misaligned.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(s, "Misaligned (broken) joints at the input configuration:");
        for m in &j.misaligned {
            let _ = writeln!(
                s,
                "   {} ({})  {}  residual {}",
                m.equation.name,
                m.equation.kind,
                m.equation.equation,
                fmt_residual(m.residual, m.residual_unit)
            );
        }
        if !j.analysed_as_repaired.is_empty() {
            let _ = writeln!(
                s,
                "   DOF and redundancy were found with these elements repaired in place: {}.",
                j.analysed_as_repaired.join(", ")
            );
        }
        match &j.after_assembly {
            Some(AfterAssemblyJson {
                converged: true,
                dof: Some(dof),
                redundant: Some(red),
            }) => {
                let same = *dof == j.dof && red.len() == j.redundant.len();
                let _ = writeln!(
                    s,
                    "   Assembled (as `linkage ic` and every analysis assemble it): {dof} Degrees \
                     of Freedom, {} redundant constraint equation(s){}.",
                    red.len(),
                    if same {
                        ", as above"
                    } else {
                        "; these counts, not the ones above, hold for the analyses (the repaired \
                         input pose is not the assembled one)"
                    }
                );
            }
            Some(_) => {
                let _ = writeln!(
                    s,
                    "   The assembly did not converge: run `linkage ic` for the equations left \
                     unsatisfied."
                );
            }
            None => {
                let _ = writeln!(s, "   Run `linkage ic` to assemble the model.");
            }
        }
    }
    let mut list = |title: &str, names: &[String]| {
        if !names.is_empty() {
            let _ = writeln!(s);
            let _ = writeln!(s, "{title}: {}", names.join(", "));
        }
    };
    list("Parts with no constraint", &j.unconstrained_parts);
    list("Parts not connected to ground", &j.ungrounded_parts);
    if !j.massless_free.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(s, "Massless parts whose motion the constraints do not determine (dynamics needs their inertia):");
        for m in &j.massless_free {
            let _ = writeln!(s, "   {}  free: {}", m.name, m.free_coordinates.join(", "));
        }
    }
    if !j.near_ties.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Independent equations close to the rank tolerance (the pose may be near-singular):"
        );
        for e in &j.near_ties {
            let _ = writeln!(s, "   {} {}", e.name, e.equation);
        }
    }
    for w in &j.warnings {
        let _ = writeln!(s);
        let _ = write!(s, "{w}");
    }
    let not_run = crate::coverage::verify_text(&j.not_run);
    if !not_run.is_empty() {
        let _ = writeln!(s);
        s.push_str(&not_run);
    }
    if let Some(line) = not_assembled_line(j) {
        let _ = writeln!(s);
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(s);
    let findings = !j.assembled
        || !j.misaligned.is_empty()
        || !j.unconstrained_parts.is_empty()
        || !j.ungrounded_parts.is_empty()
        || !j.massless_free.is_empty()
        || j.redundant.iter().any(|r| r.consistent == Some(false));
    let later = crate::coverage::refusal_verdict(&j.later_refused_by);
    let _ = writeln!(
        s,
        "{}{later}",
        if findings || !later.is_empty() {
            "Model verified with findings (see above)"
        } else {
            "Model verified successfully"
        }
    );
    s
}

/// Appends `x` signed with four decimals (`+7071.4214`, `-0.6124`), as `{:+.4}` writes it.
/// Coefficients of a redundancy are many (six per redundant row), so the common case is
/// printed from the integer `round(x·10⁴)` rather than through the exact float formatter.
/// Appends `text` left-aligned in `width` characters (as `{:<width$}`).
fn push_padded(s: &mut String, text: &str, width: usize) {
    s.push_str(text);
    let n = text.chars().count();
    s.extend(std::iter::repeat_n(' ', width.saturating_sub(n)));
}

fn push_coefficient(s: &mut String, x: f64) {
    use std::fmt::Write as _;
    let scaled = (x * 1e4).round();
    if scaled.is_finite() && scaled.abs() < 1e15 {
        let n = scaled.abs() as u64;
        let sign = if x.is_sign_negative() && n > 0 {
            '-'
        } else {
            '+'
        };
        let _ = write!(s, "{sign}{}.{:04}", n / 10_000, n % 10_000);
    } else {
        let _ = write!(s, "{x:+.4}");
    }
}

#[cfg(test)]
mod coefficient_tests {
    use super::push_coefficient;

    #[test]
    fn coefficients_print_as_the_float_formatter_does() {
        for x in [
            7071.421356,
            -7071.421356,
            0.612372,
            -0.353553,
            1.0,
            -1.0,
            10000.5,
            123.45678,
        ] {
            let mut s = String::new();
            push_coefficient(&mut s, x);
            assert_eq!(s, format!("{x:+.4}"));
        }
        // Rounding noise is 0 without a sign; huge values fall back to the formatter.
        let mut s = String::new();
        push_coefficient(&mut s, -1e-9);
        assert_eq!(s, "+0.0000");
        s.clear();
        push_coefficient(&mut s, -3e20);
        assert_eq!(s, format!("{:+.4}", -3e20));
    }
}
