//! Predicted region starts: at zero damping every region of y′ = (B0 + β cos φt B1)y
//! starts at β = 0 on φ = |ω_i − ω_j|/k for two eigenvalues λ = jω of B0 whose combination
//! is of sum type — a forward and a backward whirl, ω_fi + ω_bj — with k = 1, 2, …
//! (docs/model.md, section 5). At rest forward and backward coincide: 2ω_p and ω_p + ω_q.

use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::{ModesResult, Whirl};
use crate::analysis::{AnalysisError, Interval};
use serde::Serialize;

/// Simple (one mode with itself, at rest) or combination.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RegionKind {
    /// 2ω_p/k at rest.
    Simple,
    /// (ω_p + ω_q)/k.
    Combination,
}

/// A predicted region start.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Seed {
    /// e.g. `f1+b1`, `f1+r1`, `2 n1`, `n1+n2`.
    pub label: String,
    /// Simple (2ω_i/k) or combination ((ω_i + ω_j)/k).
    pub kind: RegionKind,
    /// Order k of the resonance (−).
    pub order: usize,
    /// (ω_i + ω_j)/k (rad/s).
    pub phi: f64,
    /// ω_i, the forward whirl (eigenvalue +jω_i of B0) (rad/s).
    pub forward: f64,
    /// ω_j, the backward whirl (eigenvalue −jω_j of B0) (rad/s).
    pub backward: f64,
    /// (i, j): indices of the forward and backward whirls among the reduced model's
    /// (each ascending), which identify the pair across nearby designs.
    pub pair: (usize, usize),
}

impl Seed {
    /// The same pair at order `k`: start (ω_i + ω_j)/k.
    pub fn at_order(&self, k: usize) -> Seed {
        Seed { order: k, phi: (self.forward + self.backward) / k as f64, ..self.clone() }
    }
}

/// Name of a reduced whirl: the tag of the nearest full-model whirl of the same direction
/// (`f1`, `b2`, …; electrical ones without the whirl letter, `r1`, `s2`, as in ω_ej), or,
/// without the full model, the whirl letter and the frequency (`f399`).
fn name(full: Option<&ModesResult>, w: f64, whirl: Whirl) -> String {
    full.and_then(|full| {
        full.modes
            .iter()
            .filter(|m| m.whirl == whirl)
            .min_by(|a, b| (a.frequency - w).abs().total_cmp(&(b.frequency - w).abs()))
            .map(|m| if m.label.chars().next().is_some_and(|c| c.is_ascii_digit()) { m.tag() } else { m.label.clone() })
    })
    .unwrap_or_else(|| format!("{}{w:.0}", whirl.letter()))
}

/// Name of a reduced whirl of the real coordinates: the tag of the nearest full-model
/// whirl of any direction (electrical ones by their label, as [`name`]), or `w399`.
fn any_name(full: Option<&ModesResult>, w: f64) -> String {
    full.and_then(|full| {
        full.modes.iter().min_by(|a, b| (a.frequency - w).abs().total_cmp(&(b.frequency - w).abs())).map(|m| {
            if m.label.chars().next().is_some_and(|c| c.is_ascii_digit()) {
                m.tag()
            } else {
                m.label.clone()
            }
        })
    })
    .unwrap_or_else(|| format!("w{w:.0}"))
}

/// All predicted starts in `range` (rad/s) up to order `max_order`, sorted by φ; labelled
/// after the full model's whirls when `full` is given.
pub fn seeds(
    fs: &FloquetSystem,
    full: Option<&ModesResult>,
    range: Interval,
    max_order: usize,
) -> Result<Vec<Seed>, AnalysisError> {
    let (f, b) = fs.whirls()?;
    let rest = fs.paired();
    // Real coordinates: a whirl is named after the nearest full-model whirl of any
    // direction (its tag, f1, b2, m1, or its electrical label); at rest with `n`.
    let real_name = |w: f64| {
        let tag = any_name(full, w);
        if fs.speed == 0.0 {
            let mut c = tag.chars();
            match c.next() {
                Some('f' | 'b' | 'm') if tag.chars().nth(1).is_some_and(|d| d.is_ascii_digit()) => {
                    format!("n{}", c.as_str())
                }
                _ => tag,
            }
        } else {
            tag
        }
    };
    let mut out = Vec::new();
    for (i, wf) in f.iter().enumerate() {
        for (j, wb) in b.iter().enumerate() {
            if rest && j < i {
                continue; // at rest f_i + b_j = f_j + b_i: keep one
            }
            let (label, kind) = if rest {
                let (ni, nj) = if fs.reduced.real {
                    (real_name(*wf), real_name(*wb))
                } else {
                    (
                        name(full, *wf, Whirl::Forward).replacen('f', "n", 1),
                        name(full, *wb, Whirl::Forward).replacen('f', "n", 1),
                    )
                };
                if i == j {
                    (format!("2 {ni}"), RegionKind::Simple)
                } else {
                    (format!("{ni}+{nj}"), RegionKind::Combination)
                }
            } else {
                (
                    format!("{}+{}", name(full, *wf, Whirl::Forward), name(full, *wb, Whirl::Backward)),
                    RegionKind::Combination,
                )
            };
            for k in 1..=max_order {
                let phi = (wf + wb) / k as f64;
                if range.contains(phi) {
                    out.push(Seed {
                        label: label.clone(),
                        kind,
                        order: k,
                        phi,
                        forward: *wf,
                        backward: *wb,
                        pair: (i, j),
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| a.phi.total_cmp(&b.phi).then(a.pair.cmp(&b.pair)).then(a.order.cmp(&b.order)));
    Ok(out)
}
