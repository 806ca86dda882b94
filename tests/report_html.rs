//! `report.html` of the widest-band design (2 starts of 8 iterations, as in
//! tests/reproducibility.rs: the page is checked, not the optimum), opened in headless Chromium (Debian's
//! `chromium`, installed by `.ci/run` when missing): the page loads with every network
//! request refused, every figure renders, the page-one answer (the tuned band and
//! circuit of report.json) is in the rendered text, and a screenshot is written.
//!
//! The check runs on a copy of the page with a script added that, once the page has
//! loaded, records what rendered and any request the page's Content Security Policy
//! (`default-src 'none'`) refused; Chromium prints the DOM after it (`--dump-dom`).
//! Without a browser the test fails, saying why, unless `ROTORSHUNT_SKIP_BROWSER=1`.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Against hangs only: Chromium is killed after this (it starts in about a second; a page
/// without network has nothing to wait for).
const BROWSER_HANG_TIMEOUT_SECONDS: u64 = 60;

fn chromium() -> Option<PathBuf> {
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"].iter().map(PathBuf::from).find(|p| p.exists())
}

fn browser(bin: &Path, args: &[&str]) -> std::process::Output {
    let mut c = Command::new("timeout");
    c.arg(BROWSER_HANG_TIMEOUT_SECONDS.to_string()).arg(bin);
    // No sandbox: CI runs as root, where Chromium's sandbox refuses to start. Every host
    // name resolves to nothing, so no request could leave the machine anyway.
    c.args(["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--no-first-run"]);
    c.arg("--host-resolver-rules=MAP * ~NOTFOUND");
    c.args(args);
    c.output().expect("run chromium")
}

/// The script added to the check copy: what rendered, and refused requests.
const CHECK: &str = r#"<script>
var refused = 0;
document.addEventListener('securitypolicyviolation', function () { refused += 1; });
window.addEventListener('load', function () {
  var imgs = Array.from(document.images);
  var svgs = Array.from(document.querySelectorAll('figure svg'));
  var ok = function (r) { return r.width > 10 && r.height > 10; };
  var result = {
    images: imgs.length,
    images_rendered: imgs.filter(function (i) { return i.complete && i.naturalWidth > 0 && ok(i.getBoundingClientRect()); }).length,
    svgs: svgs.length,
    svgs_rendered: svgs.filter(function (s) { return s.childElementCount > 0 && ok(s.getBoundingClientRect()); }).length,
    refused: refused,
  };
  document.body.setAttribute('data-check', JSON.stringify(result));
});
</script>"#;

#[test]
fn the_design_report_renders_offline_in_chromium() {
    let Some(bin) = chromium() else {
        if std::env::var("ROTORSHUNT_SKIP_BROWSER").as_deref() == Ok("1") {
            eprintln!("SKIPPED: no chromium (ROTORSHUNT_SKIP_BROWSER=1)");
            return;
        }
        panic!("no chromium at /usr/bin/chromium: `apt-get install chromium` (.ci/run does), or set ROTORSHUNT_SKIP_BROWSER=1");
    };
    let dir = common::scratch("report-html");
    let out = dir.join("design");
    let run = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(["design", &common::problem_path("design-widest-band.toml"), "--out", out.to_str().unwrap(), "--quiet"])
        .args(["--set", "design.starts=1", "--set", "design.max_iterations=3"])
        .args(["--set", "design.phi_range=[900.0, 1600.0]"])
        .args(common::QUICK_BASIS_ARGS)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let page = std::fs::read_to_string(out.join("report.html")).expect("report.html written");
    // Self-contained: no scripts, style sheets, frames or images fetched from anywhere.
    for bad in ["<script", "<link", "<iframe", "src=\"http", "src=\"file", "url(http"] {
        assert!(!page.contains(bad), "report.html contains {bad}");
    }
    assert!(page.contains("default-src 'none'"), "no Content Security Policy");

    // The check copy: the same page, with inline scripts allowed and the check added.
    let check = page
        .replace("default-src 'none';", "default-src 'none'; script-src 'unsafe-inline';")
        .replace("</body>", &format!("{CHECK}\n</body>"));
    let check_path = dir.join("report-check.html");
    std::fs::write(&check_path, check).unwrap();
    let url = format!("file://{}", check_path.display());
    let dom = browser(&bin, &["--virtual-time-budget=5000", "--dump-dom", &url]);
    let dom_text = String::from_utf8_lossy(&dom.stdout);
    assert!(dom.status.success(), "chromium failed: {}", String::from_utf8_lossy(&dom.stderr));
    let start = dom_text.find("data-check=\"").expect("the check script ran") + "data-check=\"".len();
    let end = start + dom_text[start..].find('"').unwrap();
    let json = dom_text[start..end].replace("&quot;", "\"");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {json}"));
    println!("report.html in chromium: {v}");
    let n = |k: &str| v[k].as_u64().unwrap_or_else(|| panic!("{k}: {v}"));
    assert_eq!(n("refused"), 0, "requests refused by the page's policy: {v}");
    assert!(n("images") + n("svgs") >= 3, "fewer than three figures: {v}");
    assert_eq!(n("images_rendered"), n("images"), "{v}");
    assert_eq!(n("svgs_rendered"), n("svgs"), "{v}");

    // The page-one answer: the tuned band and the tuned circuit of report.json, in the
    // rendered text, before the first figure.
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let band = &report["outcome"]["after_bands"][0]["band"]["band"];
    let first_figure = dom_text.find("<figure").unwrap_or(dom_text.len());
    let answer = &dom_text[..first_figure];
    for x in [band["lo"].as_f64().unwrap(), band["hi"].as_f64().unwrap()] {
        let s = format!("{x:.2}");
        assert!(answer.contains(&s), "band edge {s} not on page one");
    }
    for b in report["branches_after"].as_array().unwrap() {
        let s = format!("{:.2}", b["tuning_frequency"].as_f64().unwrap());
        assert!(answer.contains(&s), "tuned frequency {s} not on page one");
    }

    // A screenshot of the page as a reader opens it.
    let shot = dir.join("report.png");
    let url = format!("file://{}", out.join("report.html").display());
    let s = browser(
        &bin,
        &["--window-size=1200,1600", "--hide-scrollbars", &format!("--screenshot={}", shot.display()), &url],
    );
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let png = std::fs::read(&shot).expect("screenshot written");
    assert!(png.starts_with(b"\x89PNG") && png.len() > 20_000, "screenshot of {} bytes", png.len());
    println!("screenshot: {} ({} bytes)", shot.display(), png.len());
}
