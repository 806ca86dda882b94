//! Plain-text summaries for the terminal: the model check and the whirl-mode table.

use crate::analysis::modes::WhirlMode;
use crate::analysis::Rotor;
use crate::model::{Beam, Circuit, CircuitState, Model, Ring, RingSupport, Section};
use std::fmt::Write;

fn ring_lines(out: &mut String, header: &str, r: &Ring) {
    let _ = writeln!(out, "  {header}:");
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

/// The circuit's state and branches (inductance, and tuning by Eq. 4 with `cp_t`).
fn circuit_lines(out: &mut String, indent: &str, c: &Circuit, cp_t: f64) {
    let _ = writeln!(
        out,
        "{indent}circuit: {} with {} branch(es){}",
        c.state,
        c.branches.len(),
        if c.state == CircuitState::Closed { "" } else { " (not connected in this state)" }
    );
    for (i, b) in c.branches.iter().enumerate() {
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
            format!("tuned to {} rad/s (Eq. 4)", fixed(b.tuning_frequency(cp_t), 1))
        };
        let _ = writeln!(
            out,
            "{indent}  branch {}: C_f = {:.4e} F, L = {} H, R = {} ohm, {tuning}",
            i + 1,
            b.c_f,
            fixed(b.inductance, 4),
            b.resistance,
        );
    }
}

/// The paper's layout, as the shorthand gives it: rings `left` at node 0 and `right` at
/// the last node on one circuit, no plain bearing. `check` prints it as it always has.
fn paper_layout(m: &Model) -> Option<(&RingSupport, &RingSupport)> {
    match (&m.rings[..], m.bearings.is_empty(), m.shared_circuit()) {
        ([l, r], true, Some(_))
            if l.name == "left" && r.name == "right" && l.node == 0 && r.node == m.shaft.last_node() =>
        {
            Some((l, r))
        }
        _ => None,
    }
}

fn shaft_lines(out: &mut String, m: &Model) {
    let shaft = &m.shaft;
    if let [s] = &shaft.sections[..] {
        if s.inner_diameter == 0.0 && s.is_uniform_rayleigh() && s.layers.is_empty() {
            let _ = writeln!(
                out,
                "  shaft: L = {} m, r = {} m, {} Rayleigh elements ({} nodes), mass {:.4} kg",
                shaft.length(),
                s.outer_diameter / 2.0,
                shaft.elements(),
                shaft.nodes(),
                shaft.mass()
            );
            return;
        }
    }
    let timoshenko: usize =
        shaft.sections.iter().filter(|s| matches!(s.beam, Beam::Timoshenko { .. })).map(|s| s.elements).sum();
    let kinds = match timoshenko {
        0 => format!("{} Rayleigh elements", shaft.elements()),
        t if t == shaft.elements() => format!("{t} Timoshenko elements"),
        t => format!("{} elements ({} Rayleigh, {t} Timoshenko)", shaft.elements(), shaft.elements() - t),
    };
    let _ = writeln!(
        out,
        "  shaft: L = {:.4} m, {} section(s), {kinds} ({} nodes), mass {:.4} kg",
        shaft.length(),
        shaft.sections.len(),
        shaft.nodes(),
        shaft.mass()
    );
    let (mut x, mut node) = (0.0, 0);
    for (i, s) in shaft.sections.iter().enumerate() {
        if s.is_uniform_rayleigh() && s.layers.is_empty() {
            let _ = writeln!(
                out,
                "    section {}: x = {:.4} to {:.4} m (nodes {} to {}), D = {} m, d = {} m, E = {:.4e} Pa, rho = {} kg/m^3, A = {:.4e} m^2, I = {:.4e} m^4",
                i + 1,
                x,
                x + s.length,
                node,
                node + s.elements,
                s.outer_diameter,
                s.inner_diameter,
                s.youngs_modulus,
                s.density,
                s.area(),
                s.inertia()
            );
        } else {
            let _ = writeln!(
                out,
                "    section {}: x = {:.4} to {:.4} m (nodes {} to {}), {}",
                i + 1,
                x,
                x + s.length,
                node,
                node + s.elements,
                tube_text(s)
            );
        }
        for (j, layer) in s.layers.iter().enumerate() {
            let _ = writeln!(out, "      layer {}: {}", j + 2, tube_text(layer));
        }
        x += s.length;
        node += s.elements;
    }
}

/// A Timoshenko, tapered or layer tube in words: diameters, material, beam theory.
fn tube_text(s: &Section) -> String {
    let diameters = if s.is_uniform() {
        format!("D = {} m, d = {} m", s.outer_diameter, s.inner_diameter)
    } else {
        format!(
            "tapered D = {} to {} m, d = {} to {} m",
            s.outer_diameter, s.outer_diameter_right, s.inner_diameter, s.inner_diameter_right
        )
    };
    let beam = match s.beam {
        Beam::Rayleigh => "Rayleigh".to_string(),
        Beam::Timoshenko { shear_modulus, shear_coefficient } => {
            let e = s.element(0);
            let kappa = e.shear.map_or(0.0, |kg| kg / shear_modulus);
            let given = if shear_coefficient.is_some() { "given" } else { "Cowper" };
            format!(
                "Timoshenko, G = {shear_modulus:.4e} Pa, kappa = {kappa:.4} ({given}{}), Phi = {:.4e}",
                if s.is_uniform() { "" } else { ", first element" },
                e.shear_parameter()
            )
        }
    };
    format!("{diameters}, E = {:.4e} Pa, rho = {} kg/m^3, {beam}", s.youngs_modulus, s.density)
}

/// The `check` summary: DOF counts, ring stiffnesses (per ring), branch inductances, P_cr.
pub fn check_text(rotor: &Rotor, title: &str) -> String {
    let m = &rotor.model;
    let d = &rotor.system.dofs;
    let mut out = String::new();
    let _ = writeln!(out, "{title}");
    shaft_lines(&mut out, m);
    for (i, disk) in m.disks.iter().enumerate() {
        let _ = writeln!(
            out,
            "  disk {}: node {} (x = {:.4} m), m = {} kg, J_p = {} kg m^2, J_d = {} kg m^2",
            i + 1,
            disk.node,
            m.shaft.node_position(disk.node),
            disk.mass,
            disk.polar_inertia,
            disk.diametral_inertia
        );
    }
    let _ = writeln!(out, "  rotor mass (shaft + disks): {:.4} kg", m.rotor_mass());
    let _ = writeln!(
        out,
        "  DOFs (complex): {} shaft + {} ring + {} charge = {}; state vector {}",
        d.shaft_dofs(),
        d.rings(),
        d.charges(),
        d.len(),
        2 * d.len()
    );
    let mut counts = [0usize; 2];
    for b in &m.bearings {
        let n = &mut counts[usize::from(b.kind == crate::model::SupportKind::Seal)];
        *n += 1;
        let place = format!("{} {}: node {} (x = {:.4} m)", b.kind, n, b.node, m.shaft.node_position(b.node));
        if b.is_isotropic() {
            let _ = writeln!(
                out,
                "  {place}, k = {:.3e} N/m, c = {} N s/m, mass = {} kg",
                b.stiffness(),
                b.damping(),
                b.mass
            );
        } else {
            let at = b.matrices_at(m.speed);
            let table = match (b.speeds.first(), b.speeds.last()) {
                (Some(lo), Some(hi)) => format!(", tables over {lo}…{hi} rad/s ({} speeds)", b.speeds.len()),
                _ => String::new(),
            };
            let _ = writeln!(
                out,
                "  {place}, at {} rad/s: K = [[{:.3e}, {:.3e}], [{:.3e}, {:.3e}]] N/m, C = [[{:.3e}, {:.3e}], [{:.3e}, {:.3e}]] N s/m, mass = {} kg{table}",
                m.speed,
                at.k[0][0], at.k[0][1], at.k[1][0], at.k[1][1],
                at.c[0][0], at.c[0][1], at.c[1][0], at.c[1][1],
                b.mass
            );
        }
    }
    if m.real_coordinates() {
        let _ = writeln!(out, "  coordinates: real (v, w), {} real DOFs", 2 * d.len());
    }
    match paper_layout(m) {
        Some((left, right)) => {
            ring_lines(&mut out, "left ring", &left.ring);
            if right.ring != left.ring {
                ring_lines(&mut out, "right ring", &right.ring);
            } else {
                let _ = writeln!(out, "  right ring: same as left");
            }
            circuit_lines(&mut out, "  ", &left.circuit, left.ring.cp_t);
        }
        None => {
            for r in &m.rings {
                let header = format!("ring {} at node {} (x = {:.4} m)", r.name, r.node, m.shaft.node_position(r.node));
                ring_lines(&mut out, &header, &r.ring);
                circuit_lines(&mut out, "    ", &r.circuit, r.ring.cp_t);
            }
        }
    }
    let euler = if m.shaft.sections.len() == 1 {
        "pinned-pinned Euler load pi^2 EI/L^2"
    } else {
        "pinned-pinned Euler load of the weakest section pi^2 EI_min/L^2"
    };
    let _ = writeln!(
        out,
        "  P_cr = {:.4e} N ({}; {euler} = {:.4e} N)",
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
    // The paper's labels fit 6 characters; ring-named ones (`fr1@drive`) widen the column.
    let w = modes.iter().map(|m| m.tag().chars().count()).max().unwrap_or(0).max(6);
    let _ = writeln!(out, "{:>w$} {:>9} {:>11} {:>16} {:>12}", "mode", "whirl", "kind", "frequency rad/s", "damping");
    for m in modes {
        let _ = writeln!(
            out,
            "{:>w$} {:>9} {:>11} {:>16.2} {:>12.3e}",
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
