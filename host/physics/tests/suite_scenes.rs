//! The benchmark suite's scenes in motion (`scenes/suite/`, written by its `generate.py`):
//! each loads and builds at the defaults, and the two piles keep their bodies where the
//! physics puts them (in the bin, above the ground, links not through each other).

use virtual_physics::dynamics::BodyKind;
use virtual_physics::scene::SceneFile;

fn suite_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/suite")
}

fn load(name: &str) -> SceneFile {
    SceneFile::from_path(&format!("{}/{name}.json", suite_dir().display()))
        .expect("a committed scene")
}

#[test]
fn every_suite_scene_loads_and_builds() {
    let mut names: Vec<_> = std::fs::read_dir(suite_dir())
        .expect("the suite's folder")
        .filter_map(|e| {
            let p = e.ok()?.path();
            (p.extension()? == "json").then_some(p)
        })
        .collect();
    names.sort();
    assert!(names.len() >= 9, "the suite's scenes: {names:?}");
    for p in names {
        let s = SceneFile::from_path(&p.to_string_lossy())
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(
            s.problems().is_empty(),
            "{}: {:?}",
            p.display(),
            s.problems()
        );
        let mut w = s.build().unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        w.step().unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    }
}

/// Bodies thrown spinning into the bin stay inside its walls and above the ground: the
/// walls (0.5 m thick) and the ground hold them, none is pushed through. The bound is a
/// body's largest half-size (0.45 m box half-extent, 0.5 m sphere radius: at most 0.78 m
/// from its centre to a corner) past the wall's inner face.
#[test]
fn the_tumbling_pile_stays_in_its_bin() {
    let s = load("tumble-500");
    let half = 5.0;
    let reach = (3.0f64 * 0.45 * 0.45).sqrt().max(0.5);
    let mut w = s.build().expect("builds");
    for _ in 0..120 {
        w.step().expect("steps");
    }
    for b in w.bodies().filter(|b| b.kind() == BodyKind::Dynamic) {
        let p = b.position();
        assert!(p.iter().all(|x| x.is_finite()), "finite: {p:?}");
        assert!(
            p.x.abs() <= half + reach - 0.25 && p.y.abs() <= half + reach - 0.25,
            "a body left the bin: {p:?}"
        );
        assert!(p.z >= 0.0, "a body's centre under the ground: {p:?}");
    }
}

/// The chains fall onto the ground and each other: the whole pile of 24, and the first 8 and
/// 16 of them (other sizes of the same scene). The pile is passive (gravity, contacts and
/// friction, no drive): its energy, kinetic and potential, never rises above what it started
/// with (a tolerance of 0.1 % for the integrator's error); no overlap reaches a link's
/// diameter (4 cm: a link that deep would be through what it touches); and every link's frame
/// ends above the ground less a link's radius.
#[test]
fn the_chains_pile_up_without_gaining_energy() {
    let radius = 0.02;
    for count in [8, 16, 24] {
        let mut s = load("chains-24");
        s.articulated.truncate(count);
        let mut w = s.build().expect("builds");
        let start = w.energy();
        let (mut deepest, mut highest): (f64, f64) = (0.0, start);
        for _ in 0..180 {
            w.step().expect("steps");
            deepest = deepest.max(w.max_penetration());
            highest = highest.max(w.energy());
        }
        assert!(
            highest <= start * 1.001,
            "{count} chains: energy rose from {start} J to {highest} J"
        );
        assert!(
            deepest < 2.0 * radius,
            "{count} chains: deepest overlap {deepest} m"
        );
        let trees: Vec<_> = w.tree_handles().collect();
        assert_eq!(trees.len(), count);
        for t in trees {
            let sys = w.tree(t).expect("a tree");
            for pose in sys.link_poses() {
                assert!(
                    pose.p.z > -radius,
                    "{count} chains: a link under the ground: {:?}",
                    pose.p
                );
            }
        }
    }
}
