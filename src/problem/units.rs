//! Keys in other units and pairs of alternative keys, resolved on the TOML document
//! before it is read into [`super::ProblemFile`]:
//!
//! - a speed may be given in rpm by the key with the suffix `_rpm` (`speed_rpm`,
//!   `design.speeds_rpm`, `design.speed_range_rpm`, `design.response.speeds_rpm`); it is
//!   converted at load,
//!   Ω = n·π/30 rad/s, and the rest of the program sees the rad/s key only
//!   ([`RPM_KEYS`]); on the command line, a speed range takes the suffix `rpm`
//!   (`--speeds 0:30000:500rpm`, parsed by the CLI layer);
//! - a `--set` of one key of a pair of alternatives (`node`/`position`,
//!   `inductance`/`tuning_frequency`, `cp_s`/`k_eq2`, a speed and its `_rpm` form)
//!   replaces the other in the same table when the other came from the file
//!   ([`ALTERNATIVES`]). A file that gives both keys is still refused.

use super::ProblemErrorKind as K;
use crate::analysis::limits;

pub use crate::numbers::RAD_PER_S_PER_RPM;

/// Speed keys that have an rpm form: (table path, key in rad/s, key in rpm). The table
/// path is empty for the top level, dotted for a nested table.
pub const RPM_KEYS: [(&str, &str, &str); 4] = [
    ("", "speed", "speed_rpm"),
    ("design", "speeds", "speeds_rpm"),
    ("design", "speed_range", "speed_range_rpm"),
    ("design.response", "speeds", "speeds_rpm"),
];

/// Pairs of keys of one table of which a file gives one: a `--set` of either replaces the
/// other. `node`/`position` place disks, bearings and rings; `inductance`/
/// `tuning_frequency` set a branch's L (Eq. 4); `cp_s`/`k_eq2` a ring's C_p^S (Eq. 1);
/// the speeds' rad/s and rpm forms; `shear_modulus`/`poisson_ratio` a material's G.
pub const ALTERNATIVES: [(&str, &str); 7] = [
    ("node", "position"),
    ("inductance", "tuning_frequency"),
    ("cp_s", "k_eq2"),
    ("shear_modulus", "poisson_ratio"),
    ("speed", "speed_rpm"),
    ("speeds", "speeds_rpm"),
    ("speed_range", "speed_range_rpm"),
];

/// The key that a `--set` of `path` replaces: the other key of its pair, in the same table
/// (`disks[0].position` → `disks[0].node`), or `None` when the key has no alternative.
pub fn alternative_of(path: &str) -> Option<String> {
    let (parent, last) = match path.rfind('.') {
        Some(i) => (&path[..=i], &path[i + 1..]),
        None => ("", path),
    };
    ALTERNATIVES.iter().find_map(|&(a, b)| {
        if last == a {
            Some(format!("{parent}{b}"))
        } else if last == b {
            Some(format!("{parent}{a}"))
        } else {
            None
        }
    })
}

/// A failure at a key path (as the validator's failures).
pub type Failure = (String, K);

/// Convert every rpm key of `table` to its rad/s key (Ω = n·π/30). A table that gives both
/// forms is refused ([`K::BothGiven`] at the rpm key); an rpm value is checked by the speed
/// rule ([`limits::speed`]: finite, ≥ 0) at its own key, in rpm. Returns the rad/s keys
/// that were given in rpm (`speed`, `design.speeds`, `design.response.speeds`).
pub fn convert_rpm(table: &mut toml::Table) -> Result<Vec<String>, Failure> {
    let mut converted_keys = Vec::new();
    for (parent, rad, rpm) in RPM_KEYS {
        let t = if parent.is_empty() {
            &mut *table
        } else {
            match lookup_table(table, parent) {
                Some(t) => t,
                None => continue,
            }
        };
        let key = |k: &str| full_key(parent, k);
        let Some(value) = t.get(rpm) else { continue };
        // A response's speeds are bounded (the unbalance force grows like Ω²).
        let rule = if parent == "design.response" { limits::response_speed_rpm } else { limits::speed };
        if t.contains_key(rad) {
            return Err((key(rpm), K::BothGiven(rad.into(), rpm.into())));
        }
        // `speed` is one speed; the others are lists. A value of the other shape is refused
        // at the rpm key, where the file has it.
        let list = !parent.is_empty();
        let converted = match value {
            toml::Value::Array(items) if list => toml::Value::Array(
                items
                    .iter()
                    .enumerate()
                    .map(|(i, v)| to_rad_per_s(&format!("{}[{i}]", key(rpm)), v, rule))
                    .collect::<Result<_, _>>()?,
            ),
            v if !list => to_rad_per_s(&key(rpm), v, rule)?,
            other => {
                let found = other.type_str();
                return Err((
                    key(rpm),
                    K::Schema(format!("invalid type: {found}, expected a sequence of speeds (rpm)")),
                ));
            }
        };
        t.remove(rpm);
        t.insert(rad.to_string(), converted);
        converted_keys.push(key(rad));
    }
    Ok(converted_keys)
}

/// The speeds `table` gives in rpm, before [`convert_rpm`]: each rpm key's path
/// (`speed_rpm`, `design.speeds_rpm`) and its value as given, in [`RPM_KEYS`] order. What a
/// tuned file writes back under the user's own key.
pub fn rpm_given(table: &toml::Table) -> Vec<(String, toml::Value)> {
    let mut out = Vec::new();
    for (parent, _, rpm) in RPM_KEYS {
        let mut t = Some(table);
        for part in parent.split('.').filter(|p| !p.is_empty()) {
            t = t.and_then(|t| t.get(part)).and_then(toml::Value::as_table);
        }
        if let Some(v) = t.and_then(|t| t.get(rpm)) {
            out.push((full_key(parent, rpm), v.clone()));
        }
    }
    out
}

/// One speed in rpm as rad/s.
fn to_rad_per_s(
    key: &str,
    v: &toml::Value,
    rule: fn(f64) -> Result<f64, limits::ParamError>,
) -> Result<toml::Value, Failure> {
    let n = match v {
        toml::Value::Float(x) => *x,
        toml::Value::Integer(i) => *i as f64,
        other => {
            return Err((key.into(), K::Schema(format!("invalid type: {}, expected a speed in rpm", other.type_str()))))
        }
    };
    let n = rule(n).map_err(|e| (key.to_string(), K::from(&e)))?;
    Ok(toml::Value::Float(n * RAD_PER_S_PER_RPM))
}

/// Remove from `table` the key at `path` (`disks[0].node`), if it is there.
pub fn remove_path(table: &mut toml::Table, path: &str) {
    let (parent, last) = match path.rfind('.') {
        Some(i) => (&path[..i], &path[i + 1..]),
        None => {
            table.remove(path);
            return;
        }
    };
    if let Some(t) = lookup_table(table, parent) {
        t.remove(last);
    }
}

/// True when `table` has a value at `path`.
pub fn has_path(table: &mut toml::Table, path: &str) -> bool {
    match path.rfind('.') {
        Some(i) => lookup_table(table, &path[..i]).is_some_and(|t| t.contains_key(&path[i + 1..])),
        None => table.contains_key(path),
    }
}

/// The table at `path` (`circuit.branches[1]`), if the document has one there.
fn lookup_table<'a>(table: &'a mut toml::Table, path: &str) -> Option<&'a mut toml::Table> {
    let mut cur = table;
    for part in path.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        let mut value = cur.get_mut(name)?;
        while let Some(stripped) = rest.strip_prefix('[') {
            let end = stripped.find(']')?;
            let i: usize = stripped[..end].parse().ok()?;
            value = value.as_array_mut()?.get_mut(i)?;
            rest = &stripped[end + 1..];
        }
        cur = value.as_table_mut()?;
    }
    Some(cur)
}

/// The key a failure at `key` is blamed on in the file: a key converted from rpm
/// (`converted`, as [`convert_rpm`] returns them) or an entry of it (`design.speeds[1]`)
/// is named by the rpm key the file gives (`design.speeds_rpm[1]`); other keys as they are.
pub fn file_key(key: &str, converted: &[String]) -> String {
    for rad in converted {
        let rest = match key.strip_prefix(rad.as_str()) {
            Some(r) if r.is_empty() || r.starts_with('[') => r,
            _ => continue,
        };
        if let Some((parent, _, rpm)) = RPM_KEYS.iter().find(|(parent, r, _)| full_key(parent, r) == *rad) {
            return format!("{}{rest}", full_key(parent, rpm));
        }
    }
    key.to_string()
}

/// The rpm form's name (`speed_rpm`) of a rad/s key that has one (`speed`,
/// `design.speeds`, …), given by its full path; None for other keys.
pub fn rpm_form(path: &str) -> Option<String> {
    RPM_KEYS.iter().find_map(|(parent, rad, rpm)| (full_key(parent, rad) == path).then(|| rpm.to_string()))
}

/// The full path of `key` in the table at `parent` (empty: the top level).
fn full_key(parent: &str, key: &str) -> String {
    if parent.is_empty() {
        key.to_string()
    } else {
        format!("{parent}.{key}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_key_of_a_pair_names_the_other_in_its_table() {
        assert_eq!(alternative_of("disks[0].position").as_deref(), Some("disks[0].node"));
        assert_eq!(alternative_of("rings[1].node").as_deref(), Some("rings[1].position"));
        assert_eq!(
            alternative_of("circuit.branches[0].inductance").as_deref(),
            Some("circuit.branches[0].tuning_frequency")
        );
        assert_eq!(alternative_of("ring.right.k_eq2").as_deref(), Some("ring.right.cp_s"));
        assert_eq!(alternative_of("speed_rpm").as_deref(), Some("speed"));
        assert_eq!(alternative_of("design.speeds").as_deref(), Some("design.speeds_rpm"));
        assert_eq!(alternative_of("disks[0].mass"), None);
    }

    #[test]
    fn rpm_becomes_rad_per_s_and_both_forms_are_refused() {
        let mut t: toml::Table = toml::from_str("speed_rpm = 60\n[design]\nspeeds_rpm = [30.0, 600]\n").unwrap();
        convert_rpm(&mut t).unwrap();
        let close = |v: &toml::Value, x: f64| (v.as_float().unwrap() / x - 1.0).abs() < 1e-15;
        assert!(close(&t["speed"], 2.0 * std::f64::consts::PI));
        assert!(!t.contains_key("speed_rpm"));
        let speeds = t["design"]["speeds"].as_array().unwrap();
        assert!(close(&speeds[0], std::f64::consts::PI));
        assert!(close(&speeds[1], 20.0 * std::f64::consts::PI));
        let mut both: toml::Table = toml::from_str("speed = 1.0\nspeed_rpm = 60\n").unwrap();
        let (key, kind) = convert_rpm(&mut both).unwrap_err();
        assert_eq!(key, "speed_rpm");
        assert_eq!(kind, K::BothGiven("speed".into(), "speed_rpm".into()));
        let mut negative: toml::Table = toml::from_str("[design]\nspeeds_rpm = [1.0, -3.0]\n").unwrap();
        let (key, kind) = convert_rpm(&mut negative).unwrap_err();
        assert_eq!(key, "design.speeds_rpm[1]");
        assert_eq!(kind, K::Negative(-3.0));
    }

    #[test]
    fn keys_converted_from_rpm_are_blamed_on_the_rpm_key() {
        let converted = vec!["speed".to_string(), "design.speed_range".to_string()];
        assert_eq!(super::file_key("speed", &converted), "speed_rpm");
        assert_eq!(super::file_key("design.speed_range[1]", &converted), "design.speed_range_rpm[1]");
        assert_eq!(super::file_key("design.speeds[0]", &converted), "design.speeds[0]");
        assert_eq!(super::file_key("speedx", &converted), "speedx");
    }

    #[test]
    fn speed_keys_know_their_rpm_form() {
        assert_eq!(super::rpm_form("speed").as_deref(), Some("speed_rpm"));
        assert_eq!(super::rpm_form("design.speed_range").as_deref(), Some("speed_range_rpm"));
        assert_eq!(super::rpm_form("shaft.length"), None);
    }
}
