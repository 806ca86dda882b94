//! Plain-text summaries for the terminal: the model check and the whirl-mode table.

use crate::analysis::modes::WhirlMode;
use crate::analysis::Rotor;
use crate::model::{CircuitState, Ring};
use std::fmt::Write;

fn ring_lines(out: &mut String, name: &str, r: &Ring) {
    let _ = writeln!(out, "  {name} ring:");
    let _ = writeln!(out, "    k_eq   = {:.3e} N/m   (Eq. 1: bearing and ring structure in series)", r.k_eq());
    let _ = writeln!(out, "    k_eq1  = {:.3e} N/m   (Eq. 1: piezo stacks)", r.k_eq1());
    let _ = writeln!(out, "    k_eq2  = {:.3e} N/m   (Eq. 1: electromechanical coupling)", r.k_eq2());
    let _ = writeln!(
        out,
        "    C_p^S  = {:.4e} F,  C_p^T = {:.4e} F,  gamma = 2 cot^2(beta) theta_p^2 = {:.4} ",
        r.cp_s,
        r.cp_t,
        r.gamma()
    );
    let _ = writeln!(out, "    m_b    = {} kg,  eta = {} N s/m", r.m_b, r.eta);
}

/// The `check` summary: DOF counts, ring stiffnesses, branch inductances, P_cr.
pub fn check_text(rotor: &Rotor, title: &str) -> String {
    let m = &rotor.model;
    let d = &rotor.system.dofs;
    let mut out = String::new();
    let _ = writeln!(out, "{title}");
    let _ = writeln!(
        out,
        "  shaft: L = {} m, r = {} m, {} Rayleigh elements ({} nodes), mass {:.4} kg",
        m.shaft.length,
        m.shaft.radius,
        m.shaft.elements,
        m.shaft.nodes(),
        m.shaft.mass()
    );
    for (i, disk) in m.disks.iter().enumerate() {
        let _ = writeln!(
            out,
            "  disk {}: node {} (x = {:.4} m), m = {} kg, J_p = {} kg m^2, J_d = {} kg m^2",
            i + 1,
            disk.node,
            disk.node as f64 * m.shaft.element_length(),
            disk.mass,
            disk.polar_inertia,
            disk.diametral_inertia
        );
    }
    let _ = writeln!(out, "  rotor mass (shaft + disks): {:.4} kg", m.rotor_mass());
    let _ = writeln!(
        out,
        "  DOFs (complex): {} shaft + 2 ring + {} charge = {}; state vector {}",
        d.shaft_dofs(),
        2 * d.branches,
        d.len(),
        2 * d.len()
    );
    ring_lines(&mut out, "left", &m.left);
    if m.right != m.left {
        ring_lines(&mut out, "right", &m.right);
    } else {
        let _ = writeln!(out, "  right ring: same as left");
    }
    let _ = writeln!(
        out,
        "  circuit: {} with {} branch(es){}",
        m.circuit.state,
        m.circuit.branches.len(),
        if m.circuit.state == CircuitState::Closed { "" } else { " (not connected in this state)" }
    );
    for (i, b) in m.circuit.branches.iter().enumerate() {
        // Fixed decimals in the usual range, exponent form outside it (L = 1e300 H is not
        // 301 digits, and L = 1e-9 H not "0.0000").
        let fixed = |v: f64, decimals: usize| {
            if v == 0.0 || (1e-3..1e7).contains(&v.abs()) {
                format!("{v:.decimals$}")
            } else {
                format!("{v:.4e}")
            }
        };
        let tuning = if b.inductance == 0.0 {
            "not tuned (L = 0: a massless charge)".to_string()
        } else {
            format!("tuned to {} rad/s (Eq. 4)", fixed(b.tuning_frequency(m.left.cp_t), 1))
        };
        let _ = writeln!(
            out,
            "    branch {}: C_f = {:.4e} F, L = {} H, R = {} ohm, {tuning}",
            i + 1,
            b.c_f,
            fixed(b.inductance, 4),
            b.resistance,
        );
    }
    let _ = writeln!(
        out,
        "  P_cr = {:.4e} N ({}; pinned-pinned Euler load pi^2 EI/L^2 = {:.4e} N)",
        rotor.critical_load,
        if m.load.critical_load.is_some() { "given" } else { "computed, open-circuit supports" },
        m.shaft.euler_load()
    );
    let _ = writeln!(
        out,
        "  static load alpha P_cr = {} x P_cr = {:.4e} N; speed {} rad/s",
        m.load.alpha,
        rotor.static_load(),
        m.speed
    );
    out
}

/// A fixed-width table of whirl modes.
pub fn modes_text(modes: &[WhirlMode], speed: f64, critical_load: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "speed {speed} rad/s, P_cr = {critical_load:.4e} N");
    let _ = writeln!(out, "{:>6} {:>9} {:>11} {:>16} {:>12}", "mode", "whirl", "kind", "frequency rad/s", "damping");
    for m in modes {
        let _ = writeln!(
            out,
            "{:>6} {:>9} {:>11} {:>16.2} {:>12.3e}",
            m.tag(),
            format!("{:?}", m.whirl).to_lowercase(),
            format!("{:?}", m.kind).to_lowercase(),
            m.frequency,
            m.damping_ratio
        );
    }
    for m in modes {
        if let Some(flag) = &m.flag {
            let _ = writeln!(out, "note: mode {} is flagged: {flag}", m.tag());
        }
    }
    out
}
