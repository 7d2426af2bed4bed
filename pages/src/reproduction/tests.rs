//! The compute and write phases apart: results through JSON and back are the same results, and
//! the page written from them is the same page.

use std::path::{Path, PathBuf};

use super::*;
use reproduce::{Field, Side, UNITS, Unit, UnitResult, compute, units};
use swarm_sim::waves::SNAPSHOTS;

fn options(docs: PathBuf) -> Options {
    Options {
        seed: 1,
        docs,
        quiet: true,
        placement: DEFAULT_PLACEMENT,
    }
}

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("cimax-repro-{name}-{}", std::process::id()))
}

/// `r` through one line of JSON and back.
fn through_json(r: &UnitResult) -> UnitResult {
    let line = serde_json::to_string(r).unwrap();
    assert!(!line.contains('\n'));
    serde_json::from_str(&line).unwrap()
}

/// Every file under `a` has a twin under `b` with the same bytes, and no other file is there.
fn same_files(a: &Path, b: &Path) {
    let list = |d: &Path| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        v.sort();
        v
    };
    let (xs, ys) = (list(a), list(b));
    assert_eq!(
        xs.iter().map(|p| p.file_name()).collect::<Vec<_>>(),
        ys.iter().map(|p| p.file_name()).collect::<Vec<_>>()
    );
    for (x, y) in xs.iter().zip(&ys) {
        if x.is_dir() {
            same_files(x, y);
        } else {
            assert!(
                std::fs::read(x).unwrap() == std::fs::read(y).unwrap(),
                "{} differs",
                y.display()
            );
        }
    }
}

#[test]
fn results_of_cheap_units_read_back_the_same() {
    let opts = options(temp("cheap"));
    for unit in [
        Unit::Run(Field::Gradient),
        Unit::Refractory,
        Unit::Waves,
        Unit::Placements,
        Unit::Plateau(Side::Main, 2),
    ] {
        let r = compute(unit, &opts.runs(), &mut |_| {}).unwrap();
        let back = through_json(&r);
        // Debug prints every float as the shortest decimal that reads back to it.
        assert_eq!(format!("{back:?}"), format!("{r:?}"), "{unit}");
    }
}

#[test]
fn the_wave_written_from_json_is_the_same() {
    let r = compute(Unit::Waves, &options(temp("unused")).runs(), &mut |_| {}).unwrap();
    let back = through_json(&r);
    let (a, b) = (temp("wave-a"), temp("wave-b"));
    for (dir, r) in [(&a, &r), (&b, &back)] {
        std::fs::create_dir_all(dir).unwrap();
        let mut results = Results::default();
        results.insert(r.clone()).unwrap();
        let w = results.waves(Unit::Waves).unwrap();
        crate::figures::write_waves_csv(&dir.join("waves.csv"), w, &SNAPSHOTS).unwrap();
        crate::figures::waves_figure(&dir.join("waves.svg"), w, &SNAPSHOTS).unwrap();
    }
    same_files(&a, &b);
    std::fs::remove_dir_all(&a).ok();
    std::fs::remove_dir_all(&b).ok();
}

#[test]
fn results_are_refused_twice_or_for_another_unit() {
    let opts = options(temp("unused"));
    let r = compute(Unit::Placements, &opts.runs(), &mut |_| {}).unwrap();
    let mut results = Results::default();
    results.insert(r.clone()).unwrap();
    assert!(results.insert(r.clone()).is_err());
    let mut wrong = through_json(&r);
    wrong.unit = Unit::Speed;
    assert!(Results::default().insert(wrong).is_err());
    assert_eq!(results.missing().len(), UNITS.len() - 1);
    assert!(!results.missing().contains(&Unit::Placements));
    assert!(write(&results, &opts).is_err());
}

/// The whole page twice: written from the results as computed, and from the same results
/// through JSON lines, read back in the reverse order. Every file is the same, byte for byte
/// (the timing lines too: the wall times are results). Takes the whole page's time; run with
/// `cargo test --release -p pages -- --ignored the_whole_page`.
#[test]
#[ignore = "runs every experiment of the page (minutes in release)"]
fn the_whole_page_written_from_json_lines_is_the_same() {
    let base = temp("whole");
    let opts = options(base.join("computed"));
    let mut results = Results::default();
    for &unit in units() {
        results
            .insert(compute(unit, &opts.runs(), &mut |_| {}).unwrap())
            .unwrap();
    }
    write(&results, &opts).unwrap();
    let lines: Vec<String> = results
        .iter()
        .map(|r| serde_json::to_string(r).unwrap())
        .collect();
    let mut back = Results::default();
    for line in lines.iter().rev() {
        back.insert(serde_json::from_str(line).unwrap()).unwrap();
    }
    let again = options(base.join("from-json"));
    write(&back, &again).unwrap();
    same_files(&opts.docs, &again.docs);
    std::fs::remove_dir_all(&base).ok();
}
