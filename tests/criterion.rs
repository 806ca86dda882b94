//! The declared criterion (issue acceptance: one criterion, recorded and applied alike):
//! a growth-rate floor or a width floor in `[analysis]` widens the band past the tongues
//! it ignores, and those tongues are listed, with their reason, by `band` and by the
//! catalogue; they are real (unstable by the tolerance) and below the floor.

use crate::common;

use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::{band, catalogue, Band, Catalogue, CatalogueRequest, Ignored, RegionSettings};
use rotorshunt::analysis::{Interval, Rotor};

const WINDOW: Interval = Interval::new(100.0, 8000.0);

fn run(overrides: &[&str]) -> (FloquetSystem, Band, Catalogue) {
    let p = common::load("fig11-closed-2000.toml", overrides);
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    let s = RegionSettings::default();
    let b = band(&fs, &full, &s, WINDOW, 1230.0, 0.3).unwrap();
    let req = CatalogueRequest { range: Interval::new(1150.0, 1300.0), beta_max: 0.3, level: 0.3, track: false };
    let c = catalogue(&fs, &full, &s, &req).unwrap();
    (fs, b, c)
}

#[test]
fn floors_widen_the_band_and_list_what_they_ignore() {
    let (plain_fs, plain, plain_cat) = run(&[]);
    let plain_band = plain.band.unwrap();
    assert!(plain.ignored.is_empty() && plain_cat.ignored.is_empty(), "nothing ignored by default");
    // The paper's band is bounded above by a thin tongue around 1234 rad/s (third order,
    // growth about 0.16 1/s, 0.2 rad/s wide): checked here by plain Floquet points, not by
    // an earlier output of the band search. The point at 1234 rad/s is unstable, and the
    // band ends before it, within 0.5 rad/s (the reach of tests/band_truth.rs).
    let at_1234 = plain_fs.point_fast(&plain_fs.table(1234.0, 0.3), 0.3).summary;
    assert!(!at_1234.stable && at_1234.growth_rate < 0.2, "{at_1234:?}");
    assert!(plain_band.contains(1230.0) && plain_band.hi < 1234.0 && plain_band.hi > 1234.0 - 0.5, "{plain_band:?}");
    for (set, reason) in
        [("analysis.min_growth_rate=0.2", Ignored::SlowGrowth), ("analysis.min_tongue_width=0.5", Ignored::Narrow)]
    {
        let (fs, b, cat) = run(&[set]);
        let wide = b.band.unwrap();
        assert!(wide.hi > plain_band.hi + 10.0, "{set}: {wide:?} against {plain_band:?}");
        assert!(b.guarantee.contains(if reason == Ignored::SlowGrowth {
            "growth rate >= 0.2"
        } else {
            "width >= 0.5"
        }));
        let thin =
            b.ignored.iter().find(|t| t.extent.contains(1234.0)).unwrap_or_else(|| panic!("{set}: {:?}", b.ignored));
        assert_eq!(thin.ignored, Some(reason));
        // Real: unstable by the tolerance at the point reported, and below the floor.
        let p = fs.point_fast(&fs.table(thin.inside, 0.3), 0.3).summary;
        assert!(!p.stable, "{set}: {thin:?} is not unstable");
        match reason {
            Ignored::SlowGrowth => assert!(p.growth_rate < 0.2, "{}", p.growth_rate),
            Ignored::Narrow => assert!(thin.extent.width() < 0.5),
        }
        // The catalogue lists it too, and its bands step over it.
        assert!(cat.ignored.iter().any(|t| t.extent.contains(1234.0) && t.ignored == Some(reason)), "{set}");
        assert!(cat.band_containing(1234.0).is_some(), "{set}: catalogue band at 1234");
        eprintln!(
            "{set}: band {wide:?}, ignored {:?}",
            b.ignored.iter().map(|t| (t.label(), t.extent)).collect::<Vec<_>>()
        );
    }
}
