//! The waves section of `docs/reproduction.md` (paper Fig. 2): one wave of
//! `WaveSpec::paper` (run by `reproduce`), its figure and CSV file (drawn by
//! `pages::figures`) and the section's numbers ([`WavesSection`]).

use std::path::Path;

use serde::Serialize;

use crate::figures::{waves_figure, write_waves_csv};
use report::csv_files::fixed;
use swarm_sim::experiment::Error;
use swarm_sim::waves::{PATH_SECTORS, SNAPSHOTS, Wave, hops_from};

/// One row of the snapshot table: t, inactive, active, refractory.
type CountRow = [String; 4];

/// The wave section of `docs/reproduction.md` (`templates/reproduction/waves.md.j2`), every
/// number formatted.
#[derive(Clone, Debug, Serialize)]
pub struct WavesSection {
    agents: usize,
    diameter: String,
    degree: String,
    refractory_s: u64,
    relay_s: u64,
    cycle_s: u64,
    initiator: usize,
    start_s: u64,
    redraws: u64,
    rows: Vec<CountRow>,
    reached: usize,
    last_hop: u64,
    far: String,
    speed: String,
    end_s: u64,
    rested_s: u64,
    deliveries: u64,
    accepted: u64,
    upstream: u64,
    same_front: u64,
    already_active: u64,
    blocked: u64,
    /// Every agent transmitted exactly as many seconds after the initiation as it is hops
    /// from the initiator in the neighbour graph.
    fronts_are_hops: bool,
    accepted_once: bool,
    paths: String,
    path_sectors: usize,
}

/// The section's data from a wave.
pub fn section(w: &Wave) -> WavesSection {
    let d = w.deliveries();
    let origin = w.position(w.initiator);
    let last = w.last_hop();
    let far = (0..w.len())
        .filter(|&i| w.sent_at[i] == Some(last))
        .map(|i| (w.position(i) - origin).norm())
        .fold(0.0, f64::max);
    let paths: Vec<String> = w
        .path_ends(PATH_SECTORS)
        .into_iter()
        .map(|e| (w.path(e).len().saturating_sub(1)).to_string())
        .collect();
    WavesSection {
        agents: w.len(),
        diameter: w.spec.diameter.to_string(),
        degree: fixed(w.swarm.mean_degree(), 1),
        refractory_s: w.spec.refractory_s,
        relay_s: w.spec.config().params.wave.relay_delay.as_millis() / 1000,
        cycle_s: w.spec.cycle_s,
        initiator: w.initiator,
        start_s: w.start_s,
        redraws: w.redraws,
        rows: SNAPSHOTS
            .iter()
            .map(|&t| {
                let c = w.counts(t);
                [
                    t.to_string(),
                    c[0].to_string(),
                    c[1].to_string(),
                    c[2].to_string(),
                ]
            })
            .collect(),
        reached: w.reached(),
        last_hop: last,
        far: fixed(far, 1),
        speed: fixed(if last > 0 { far / last as f64 } else { 0.0 }, 2),
        end_s: w.end_s(),
        rested_s: w.spec.refractory_s + 1,
        deliveries: d.total,
        accepted: d.accepted,
        upstream: d.upstream,
        same_front: d.same_front,
        already_active: d.already_active,
        blocked: d.upstream + d.same_front,
        fronts_are_hops: hops_from(&w.swarm, w.initiator) == w.sent_at,
        accepted_once: w
            .accepted
            .iter()
            .enumerate()
            .all(|(i, &a)| a == u32::from(i != w.initiator && w.sent_at[i].is_some())),
        paths: join_and(&paths),
        path_sectors: PATH_SECTORS,
    }
}

/// "a, b and c".
fn join_and(xs: &[String]) -> String {
    match xs {
        [] => String::new(),
        [x] => x.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Fig. 2 for `docs/reproduction.md` from one wave `w` (of [`WaveSpec::paper`](swarm_sim::waves::WaveSpec::paper), run by
/// `reproduce`): its figure (`figs/waves.svg`) and CSV file (`figs/waves.csv`), and the
/// page's section.
///
/// # Errors
/// If a file cannot be written.
pub fn write(figs: &Path, w: &Wave) -> Result<WavesSection, Error> {
    write_waves_csv(&figs.join("waves.csv"), w, &SNAPSHOTS)?;
    waves_figure(&figs.join("waves.svg"), w, &SNAPSHOTS)?;
    Ok(section(w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarm_sim::waves::{WaveSpec, one_wave};

    #[test]
    fn every_agent_accepts_once_and_relays_at_its_hops() {
        let s = section(&one_wave(&WaveSpec::paper(), 2).unwrap());
        assert!(s.accepted_once && s.fronts_are_hops);
    }

    #[test]
    fn the_figure_the_csv_and_the_section_are_written() {
        let dir = std::env::temp_dir().join(format!("cimax-waves-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let s = write(&dir, &one_wave(&WaveSpec::paper(), 1).unwrap()).unwrap();
        let svg = std::fs::read_to_string(dir.join("waves.svg")).unwrap();
        for caption in ["(a) t = 0 s", "(e) t = 16 s", "(f) paths of"] {
            assert!(svg.contains(caption), "{caption}");
        }
        let csv = std::fs::read_to_string(dir.join("waves.csv")).unwrap();
        assert_eq!(csv.lines().count(), 81);
        assert!(csv.starts_with(
            "agent,x,y,sent_at_s,parent,state_t0,state_t2,state_t4,state_t11,state_t16\n"
        ));
        let md = crate::page::render(
            "reproduction/waves.md.j2",
            minijinja::context! { waves => s },
        )
        .unwrap();
        assert!(md.starts_with("## Waves (paper Fig. 2)\n"), "{md}");
        assert!(md.contains("| 0 | 79 | 1 | 0 |"), "{md}");
        if std::env::var_os("CIMAX_SHOW_WAVES").is_some() {
            println!("{md}\nfigure: {}", dir.display());
        } else {
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }
}
