//! The plan of a study: the study file, its listed cases and its cartesian `[sweep]`. The
//! sweep is never materialised: its size is a product computed (with an overflow check)
//! before anything is built, and each case is decoded from its index (mixed radix, the
//! last key fastest) when it is needed. Case folder names are sanitised and unique.

use super::CaseKind;
use crate::commands::Error;
use rayon::prelude::*;
use rotorshunt::analysis::limits::{self, ParamError, Quantity};
use rotorshunt::problem::source::LineIndex;
use rotorshunt::problem::study::StudyFile;
use rotorshunt::problem::{Problem, ProblemError, ProblemErrorKind};
use sha2::{Digest, Sha256};
use std::collections::{BTreeSet, HashMap};
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

/// Most cases a study may have (listed plus swept). At 0.1–1 s a regions case, 10⁶ cases
/// are days of computing on a workstation: a larger plan is more likely a sweep with one
/// key too many than an intent, and it is refused before anything is built.
pub const MAX_STUDY_CASES: u64 = 1_000_000;

/// Longest sanitised text of a case folder name (bytes, ASCII): with the hash suffix the
/// name stays far below the 255 bytes every filesystem allows, with room for
/// `write_atomic`'s temporaries beside the files inside it. Long enough for a sweep
/// case's short keys and values (`resistance=0.0,tuning_frequency=900.0`).
const SLUG_TEXT_MAX: usize = 80;

/// Hex digits of the hash suffix of a folder name whose case name had to be changed: 64
/// bits, so that even 10⁶ sweep names cut to the same first [`SLUG_TEXT_MAX`] bytes keep
/// apart (chance of any two sharing a suffix ≈ n²/2⁶⁵ ≈ 3e-8; the duplicate check in
/// [`Plan::survey`] refuses the plan if they ever do).
const SLUG_HASH_HEX: usize = 16;

/// One case to run.
#[derive(Debug, Clone)]
pub struct Case {
    /// Name (listed) or the sweep's key=value pairs joined by commas.
    pub name: String,
    /// Folder name under `cases/`: the name made safe (docs/studies.md, "Case folders").
    pub slug: String,
    /// What the case runs: the listed case's `kind`, else the study's default.
    pub kind: CaseKind,
    /// Overrides on the base problem.
    pub overrides: Vec<String>,
}

/// The folder name of a case: its name with every character other than ASCII letters,
/// digits, `-`, `_`, `.`, `=` and `,` replaced by `_`, leading and trailing `.`, `_`, `=`
/// and `,` removed (no hidden, `.` or `..` folder), cut to [`SLUG_TEXT_MAX`] bytes, `case` if
/// nothing is left; and, when that changed the name, a hash of the name appended (`-` and
/// [`SLUG_HASH_HEX`] hex digits of its SHA-256), so that names differing only in the
/// characters replaced keep apart.
pub(crate) fn slug(name: &str) -> String {
    shown_slug(name, name)
}

/// [`slug`] of the text `shown` (a sweep case's name with its keys shortened), with the
/// hash of the case's full `name` when `shown` had to be changed.
fn shown_slug(shown: &str, name: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.' | '=' | ',');
    let mapped: String = shown.chars().map(|c| if safe(c) { c } else { '_' }).collect();
    let text: String = mapped.trim_matches(['.', '_', '=', ',']).chars().take(SLUG_TEXT_MAX).collect();
    if !text.is_empty() && text == shown {
        return text;
    }
    let hash = format!("{:x}", Sha256::digest(name.as_bytes()));
    format!("{}-{}", if text.is_empty() { "case" } else { &text }, &hash[..SLUG_HASH_HEX])
}

/// The shortest trailing part of each sweep key (its last `.`-separated segments) that
/// still tells the keys apart: `rings[0].circuit.branches[0].resistance` is `resistance`
/// beside `rings[0].circuit.branches[0].tuning_frequency`, and
/// `branches[1].resistance` beside `branches[0].resistance`.
fn short_keys(keys: &[String]) -> Vec<String> {
    let tail = |k: &str, n: usize| {
        let parts: Vec<&str> = k.split('.').collect();
        parts[parts.len().saturating_sub(n)..].join(".")
    };
    let mut depth = vec![1usize; keys.len()];
    loop {
        let shown: Vec<String> = keys.iter().zip(&depth).map(|(k, &n)| tail(k, n)).collect();
        let mut changed = false;
        for i in 0..keys.len() {
            let clash = (0..keys.len()).any(|j| j != i && shown[j] == shown[i]);
            if clash && shown[i] != keys[i] {
                depth[i] += 1;
                changed = true;
            }
        }
        if !changed {
            return shown;
        }
    }
}

/// A study file read and checked: its parameters and the lazily iterated cases.
pub(crate) struct Plan {
    /// The file's parameters (its listed cases inside).
    pub(crate) study: StudyFile,
    /// The base problem file (resolved against the study file's folder).
    pub(crate) base: PathBuf,
    /// The study file's text (to locate its keys in messages).
    text: String,
    /// The sweep's keys (sorted).
    sweep_keys: Vec<String>,
    /// The sweep's keys shortened for folder names ([`short_keys`]), in the same order.
    short: Vec<String>,
    /// The sweep's keys in the order of the study file.
    file_order: Vec<String>,
    /// The sweep: per key (sorted), its overrides `key=value`.
    sweep: Vec<Vec<String>>,
    /// Cases of the sweep: the product of its value counts (0 without a sweep).
    swept: u64,
}

pub(crate) fn study_error(file: &Path, message: impl Into<String>) -> Error {
    Error::Study { file: file.display().to_string(), message: message.into() }
}

impl Plan {
    /// Read and check a study file; refuses a plan of more than [`MAX_STUDY_CASES`]
    /// cases from the counts alone.
    pub(crate) fn read(file: &Path) -> Result<Plan, Error> {
        let text = rotorshunt::problem::read_toml(file)?;
        let de = toml::Deserializer::parse(&text).map_err(|e| {
            let (location, kind) = rotorshunt::problem::syntax_error(&text, &e);
            Error::Problem(ProblemError { file: file.display().to_string(), location, key: String::new(), kind })
        })?;
        let mut study: StudyFile = serde_path_to_error::deserialize(de)
            .map_err(|e| study_error(file, format!("key `{}`: {}", e.path(), e.inner().message().trim())))?;
        let base = file.parent().unwrap_or(Path::new(".")).join(&study.base);
        let mut sweep = Vec::new();
        let mut sweep_keys = Vec::new();
        for (key, values) in std::mem::take(&mut study.sweep) {
            if values.is_empty() {
                return Err(study_error(file, format!("key `sweep.{key}`: needs at least one value")));
            }
            sweep.push(values.iter().map(|v| format!("{key}={v}")).collect::<Vec<_>>());
            sweep_keys.push(key);
        }
        let swept = if sweep.is_empty() {
            Some(0)
        } else {
            sweep.iter().try_fold(1u64, |n, values| n.checked_mul(values.len() as u64))
        };
        let cases = swept.and_then(|s| s.checked_add(study.cases.len() as u64));
        match cases {
            Some(0) => return Err(study_error(file, "no cases: give [[cases]] and/or a [sweep] table")),
            Some(n) if n <= MAX_STUDY_CASES => {}
            _ => return Err(Error::StudyTooLarge { file: file.display().to_string(), cases, limit: MAX_STUDY_CASES }),
        }
        let short = short_keys(&sweep_keys);
        // The keys where the file gives them (the map is sorted): by their offset in it.
        let index = LineIndex::new(&text);
        let mut file_order = sweep_keys.clone();
        file_order.sort_by_key(|k| index.offset(&format!("sweep.{k}")).unwrap_or(usize::MAX));
        let plan = Plan {
            study,
            base,
            text: text.to_string(),
            sweep_keys,
            short,
            file_order,
            sweep,
            swept: swept.unwrap_or(0),
        };
        plan.check_fields(file)?;
        Ok(plan)
    }

    /// A value error at `key` of the study file, with its line.
    fn located(&self, file: &Path, key: &str, kind: ProblemErrorKind) -> Error {
        let location = LineIndex::new(&self.text).locate(key);
        Error::Problem(ProblemError { file: file.display().to_string(), location, key: key.into(), kind })
    }

    /// The parameters of the regions cases by their rules ([`rotorshunt::analysis::limits`]): the
    /// same as `rotorshunt regions` and `band` apply to their flags.
    fn check_fields(&self, file: &Path) -> Result<(), Error> {
        let s = &self.study;
        let at = |key: &'static str| move |e: ParamError| self.located(file, key, (&e).into());
        let range = limits::phi_range(s.phi[0], s.phi[1]).map_err(|e| {
            self.located(file, if e.quantity == Quantity::RangeLow { "phi[0]" } else { "phi[1]" }, (&e).into())
        })?;
        let beta_max = limits::beta_max(s.beta_max).map_err(at("beta_max"))?;
        if let Some(level) = s.level {
            limits::level(level, beta_max).map_err(at("level"))?;
        }
        if let Some(p) = s.phi_op {
            limits::phi_op(p, range).map_err(at("phi_op"))?;
        }
        Ok(())
    }

    /// The kinds of the plan's cases: the study's default (its sweep's) and the listed
    /// cases' own.
    pub(crate) fn kinds(&self) -> std::collections::BTreeSet<CaseKind> {
        let mut k: std::collections::BTreeSet<CaseKind> =
            self.study.cases.iter().map(|c| c.kind.unwrap_or(self.study.kind)).collect();
        if self.swept > 0 || self.study.cases.is_empty() {
            k.insert(self.study.kind);
        }
        k
    }

    /// Every sweep value on its own, applied to the base (text `base_text`, named
    /// `base_name`) after the study's `set`: a value that makes an invalid problem alone
    /// would fail every case it is in, so the study is refused, at the value's line in the
    /// study file, before anything runs. (A listed case's own `set` stays that case's: an
    /// invalid one fails the case, recorded in the summary.) In parallel; a value costs one
    /// load of the base (~40 µs for the bundled problems).
    pub(crate) fn check_sweep(&self, file: &Path, base_text: &str, base_name: &str) -> Result<(), Error> {
        let values: Vec<(usize, usize)> =
            self.sweep.iter().enumerate().flat_map(|(k, v)| (0..v.len()).map(move |i| (k, i))).collect();
        let first_bad = values.par_iter().find_map_first(|&(k, i)| {
            let overrides: Vec<String> =
                self.study.set.iter().cloned().chain(std::iter::once(self.sweep[k][i].clone())).collect();
            Problem::from_text(base_text, base_name, &overrides).err().map(|e| (k, i, e))
        });
        match first_bad {
            None => Ok(()),
            Some((k, i, e)) => {
                let key = format!("sweep.{}[{i}]", self.sweep_keys[k]);
                let location = LineIndex::new(&self.text).locate(&key);
                Err(Error::Problem(ProblemError { file: file.display().to_string(), location, key, kind: e.kind }))
            }
        }
    }

    /// The keys the cases vary, one summary column each: the sweep's in the order of the
    /// study file, then those the listed cases `set`, in order of first appearance.
    pub(crate) fn columns(&self) -> Vec<String> {
        let mut out = self.file_order.clone();
        for c in &self.study.cases {
            for o in &c.set {
                let key = o.split_once('=').map_or(o.as_str(), |(k, _)| k.trim());
                if !out.iter().any(|k| k == key) {
                    out.push(key.to_string());
                }
            }
        }
        out
    }

    /// Number of cases (listed, then swept).
    pub(crate) fn len(&self) -> u64 {
        self.study.cases.len() as u64 + self.swept
    }

    /// The kind of case `index` (< [`Plan::len`]), without building the case.
    pub(crate) fn kind_of(&self, index: u64) -> CaseKind {
        match self.study.cases.get(index as usize) {
            Some(c) => c.kind.unwrap_or(self.study.kind),
            None => self.study.kind,
        }
    }

    /// Case `index` (< [`Plan::len`]): the listed cases in file order, then the sweep's
    /// combinations with the last key varying fastest.
    pub(crate) fn case(&self, index: u64) -> Case {
        let listed = self.study.cases.len() as u64;
        if index < listed {
            let c = &self.study.cases[index as usize];
            return Case {
                name: c.name.clone(),
                slug: slug(&c.name),
                kind: c.kind.unwrap_or(self.study.kind),
                overrides: self.study.set.iter().chain(&c.set).cloned().collect(),
            };
        }
        let mut rest = index - listed;
        let mut parts = vec![""; self.sweep.len()];
        for (part, values) in parts.iter_mut().zip(&self.sweep).rev() {
            let n = values.len() as u64;
            *part = &values[(rest % n) as usize];
            rest /= n;
        }
        let name = parts.join(",");
        let shown: Vec<String> = parts
            .iter()
            .zip(&self.sweep_keys)
            .zip(&self.short)
            .map(|((part, key), short)| format!("{short}{}", &part[key.len()..]))
            .collect();
        Case {
            slug: shown_slug(&shown.join(","), &name),
            name,
            kind: self.study.kind,
            overrides: self.study.set.iter().cloned().chain(parts.iter().map(|p| p.to_string())).collect(),
        }
    }

    /// One pass over every case: the SHA-256 of the plan (the base text, the study
    /// parameters, each case's name, kind and overrides), and the check that no two
    /// cases share a folder name, compared ignoring case (case-insensitive filesystems).
    /// Memory: one 64-bit key per case; names are compared only where keys are equal.
    pub(crate) fn survey(&self, file: &Path, base_text: &[u8]) -> Result<String, Error> {
        let s = &self.study;
        let mut h = Sha256::new();
        h.update(b"rotorshunt study plan\n");
        h.update(base_text);
        h.update(format!("\n{:?} {:?} {:?} {:?}\n", s.phi, s.beta_max, s.level, s.phi_op));
        let mut keys = Vec::with_capacity(self.len() as usize);
        for i in 0..self.len() {
            let c = self.case(i);
            h.update(format!("{:?}\n{}\n{:?}\n", c.kind, c.name, c.overrides));
            keys.push(fold_key(&c.slug));
        }
        keys.sort_unstable();
        let shared: BTreeSet<u64> = keys.windows(2).filter(|w| w[0] == w[1]).map(|w| w[0]).collect();
        if !shared.is_empty() {
            let mut seen: HashMap<String, String> = HashMap::new();
            for i in 0..self.len() {
                let c = self.case(i);
                if !shared.contains(&fold_key(&c.slug)) {
                    continue;
                }
                if let Some(other) = seen.insert(c.slug.to_ascii_lowercase(), c.name.clone()) {
                    return Err(study_error(file, duplicate_message(&other, &c)));
                }
            }
        }
        Ok(format!("{:x}", h.finalize()))
    }
}

/// A hash of the folder name compared ignoring case (in-process only).
fn fold_key(slug: &str) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    slug.to_ascii_lowercase().hash(&mut h);
    h.finish()
}

fn duplicate_message(first: &str, second: &Case) -> String {
    if first == second.name {
        format!("two cases are named `{first}`: rename one (a sweep key may list a value twice)")
    } else {
        format!(
            "cases `{first}` and `{}` would share the folder cases/{} (folder names are compared ignoring case): rename one",
            second.name, second.slug
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(text: &str) -> Result<Plan, Error> {
        let dir = std::env::temp_dir().join(format!("rotorshunt-plan-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join(format!("s{}.toml", fold_key(text)));
        std::fs::write(&file, text).unwrap();
        let p = Plan::read(&file);
        std::fs::remove_file(&file).unwrap();
        p
    }

    #[test]
    fn folder_names_are_safe_and_apart() {
        for (name, text) in [("run-1", "run-1"), ("Fig_11.b", "Fig_11.b")] {
            assert_eq!(slug(name), text, "an already safe name is kept");
        }
        let names = ["..", ".", "", "a/b", "a\\b", "a b", "a_b", "/etc/passwd", "../x", ".hidden", "Ω = 2000"];
        let slugs: Vec<String> = names.iter().map(|n| slug(n)).collect();
        for (n, s) in names.iter().zip(&slugs) {
            assert!(!s.is_empty() && !s.starts_with('.') && !s.ends_with('.'), "{n:?} -> {s:?}");
            assert!(s.bytes().all(|b| b.is_ascii_alphanumeric() || b"-_.=,".contains(&b)), "{n:?} -> {s:?}");
        }
        let distinct: BTreeSet<String> = slugs.iter().map(|s| s.to_ascii_lowercase()).collect();
        assert_eq!(distinct.len(), names.len(), "{slugs:?}");
        assert!(slug("..").starts_with("case-") && slug("").starts_with("case-"));
        let long = "x".repeat(1000);
        assert!(slug(&long).len() <= SLUG_TEXT_MAX + 1 + SLUG_HASH_HEX);
        assert_ne!(slug(&long), slug(&"x".repeat(999)));
    }

    #[test]
    fn the_sweep_is_decoded_in_nested_loop_order() {
        let p = plan(
            "base = \"b.toml\"\nset = [\"analysis.reduced_modes=4\"]\n[[cases]]\nname = \"one\"\n[sweep]\nb = [1, 2, 3]\na = [10, 20]\nc = [\"x\", \"y\"]\n",
        )
        .unwrap();
        assert_eq!(p.len(), 1 + 12);
        let mut expected = Vec::new();
        for a in ["a=10", "a=20"] {
            for b in ["b=1", "b=2", "b=3"] {
                for c in ["c=\"x\"", "c=\"y\""] {
                    expected.push(vec![a, b, c]);
                }
            }
        }
        assert_eq!(p.case(0).name, "one");
        for (i, e) in expected.iter().enumerate() {
            let c = p.case(1 + i as u64);
            assert_eq!(c.name, e.join(","));
            assert_eq!(c.overrides[0], "analysis.reduced_modes=4");
            assert_eq!(&c.overrides[1..], &e[..]);
        }
    }

    #[test]
    fn sweep_folders_keep_every_value_under_short_keys() {
        let p = plan(
            "base = \"b.toml\"\n[sweep]\n\"rings[0].circuit.branches[0].tuning_frequency\" = [900.0]\n\"rings[0].circuit.branches[0].resistance\" = [0.0, 10.0]\n",
        )
        .unwrap();
        assert_eq!(p.case(0).slug, "resistance=0.0,tuning_frequency=900.0");
        assert_eq!(p.case(1).slug, "resistance=10.0,tuning_frequency=900.0");
        assert_eq!(
            p.columns(),
            ["rings[0].circuit.branches[0].tuning_frequency", "rings[0].circuit.branches[0].resistance"]
        );
        let keys: Vec<String> =
            ["circuit.branches[0].resistance", "circuit.branches[1].resistance", "speed"].map(String::from).to_vec();
        assert_eq!(short_keys(&keys), ["branches[0].resistance", "branches[1].resistance", "speed"]);
        let text = plan("base = \"b.toml\"\n[sweep]\ntitle = [\"a b\"]\n").unwrap();
        assert!(text.case(0).slug.starts_with("title=_a_b-"), "{}", text.case(0).slug);
    }

    #[test]
    fn oversized_plans_are_refused_from_the_counts() {
        let sweep = |keys: usize, values: usize| {
            let mut s = String::from("base = \"b.toml\"\n[sweep]\n");
            for k in 0..keys {
                let v: Vec<String> = (0..values).map(|i| format!("{i}.0")).collect();
                s += &format!("k{k} = [{}]\n", v.join(", "));
            }
            s
        };
        let p = plan(&sweep(6, 10)).unwrap();
        assert_eq!(p.len(), MAX_STUDY_CASES);
        assert_eq!(p.case(MAX_STUDY_CASES - 1).name, (0..6).map(|k| format!("k{k}=9.0")).collect::<Vec<_>>().join(","));
        let listed = sweep(6, 10).replace("[sweep]", "[[cases]]\nname = \"extra\"\n[sweep]");
        match plan(&listed) {
            Err(Error::StudyTooLarge { cases: Some(n), limit, .. }) => {
                assert_eq!((n, limit), (MAX_STUDY_CASES + 1, MAX_STUDY_CASES))
            }
            other => panic!("{:?}", other.err()),
        }
        match plan(&sweep(8, 10)) {
            Err(Error::StudyTooLarge { cases: Some(n), .. }) => assert_eq!(n, 100_000_000),
            other => panic!("{:?}", other.err()),
        }
        match plan(&sweep(40, 10)) {
            Err(e @ Error::StudyTooLarge { cases: None, .. }) => {
                assert!(e.to_string().contains(&format!("more than {}", u64::MAX)), "{e}")
            }
            other => panic!("{:?}", other.err()),
        }
    }

    #[test]
    fn duplicate_folders_are_found_in_listed_and_swept_cases() {
        let listed =
            |a: &str, b: &str| format!("base = \"b.toml\"\n[[cases]]\nname = {a:?}\n[[cases]]\nname = {b:?}\n");
        for (a, b) in [("Run", "run"), ("same", "same")] {
            let e = plan(&listed(a, b)).unwrap().survey(Path::new("s.toml"), b"").unwrap_err();
            assert!(e.to_string().contains(&format!("`{a}`")), "{e}");
        }
        for (a, b) in [(".", ""), ("..", "."), ("a/b", "a_b"), ("a/b", "a\\b")] {
            plan(&listed(a, b)).unwrap().survey(Path::new("s.toml"), b"").unwrap();
        }
        let twice = plan("base = \"b.toml\"\n[sweep]\nspeed = [1000.0, 2000.0, 1000.0]\n").unwrap();
        let e = twice.survey(Path::new("s.toml"), b"").unwrap_err();
        assert!(e.to_string().contains("two cases are named `speed=1000.0`"), "{e}");
        let cased = plan("base = \"b.toml\"\n[sweep]\ntitle = [\"A\", \"a\"]\n").unwrap();
        cased.survey(Path::new("s.toml"), b"").unwrap();
        assert_ne!(cased.case(0).slug.to_ascii_lowercase(), cased.case(1).slug.to_ascii_lowercase());
    }

    #[test]
    fn a_plan_at_the_limit_is_surveyed_without_materialising_it() {
        let mut s = String::from("base = \"b.toml\"\n[sweep]\n");
        for k in 0..6 {
            s += &format!(
                "\"circuit.branches[0].k{k}\" = [{}]\n",
                (0..10).map(|i| i.to_string()).collect::<Vec<_>>().join(", ")
            );
        }
        let p = plan(&s).unwrap();
        let t = std::time::Instant::now();
        let hash = p.survey(Path::new("s.toml"), b"base").unwrap();
        eprintln!("survey of {} cases: {:.2} s", p.len(), t.elapsed().as_secs_f64());
        assert_eq!(hash.len(), 64);
    }

    #[test]
    fn the_plan_hash_follows_the_base_the_parameters_and_the_cases() {
        let text = "base = \"b.toml\"\nbeta_max = 0.5\n[sweep]\nspeed = [1000.0, 2000.0]\n";
        let hash = |text: &str, base: &[u8]| plan(text).unwrap().survey(Path::new("s.toml"), base).unwrap();
        let reference = hash(text, b"base");
        assert_eq!(reference, hash(text, b"base"));
        assert_ne!(reference, hash(text, b"other base"));
        assert_ne!(reference, hash(&text.replace("0.5", "0.6"), b"base"));
        assert_ne!(reference, hash(&text.replace("2000.0", "3000.0"), b"base"));
        assert_ne!(reference, hash(&text.replace("beta_max = 0.5", "beta_max = 0.5\nkind = \"design\""), b"base"));
    }
}
