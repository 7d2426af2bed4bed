//! The write phase of `swarm reproduce`: every file of the page (the figures and CSV files
//! under `docs/figures/`, `docs/reproduction.md`) from the units' [`Results`] alone. Nothing
//! here runs an experiment; the checks between units (the tapped runs are the courses' runs)
//! are made here.

use std::path::Path;

use super::WriteError;

use super::results::{CycleRun, Results};
use super::units::placement;
use super::units::{Field, Scene, Side, Unit};
use super::{
    COURSE_RUNS, CYCLE_RUNS, CYCLE_XS, Options, PROFILE_RUNS, Report, Summary, beyond,
    caption_cloud, markdown, sensitivity, settle,
};
use crate::csv::{
    CycleRow, write_course_csv, write_cycle_csv, write_field_csv, write_radial_csv, write_run_csv,
    write_sweep_csv,
};
use crate::figures::{self, time_course_figure};
use crate::marks;
use report::plot::{self, Line};
use reproduce::stage::Scenes;
use swarm_sim::experiment::{Arrow, Error, RadialPoint, RunOutput, SweepPoint};
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::timecourse::TimeCourse;

/// The page's view model (its numbers as the template sees them), under `docs/data/`.
pub const MODEL: &str = "reproduction-page.json";

/// Writes every file of `swarm reproduce` into `opts.docs` (`reproduction.md`) and its
/// `figures/` from `results`, which must hold every unit's; `opts.seed` and
/// `opts.placement` must be those the results were computed with (the page names them).
/// The page's wall time is [`Results::wall_s`] (its units' added up unless set), its threads the most
/// any unit ran on.
///
/// # Errors
/// If a unit has no result, the results contradict each other, or a file cannot be written.
pub fn write(results: &Results, opts: &Options) -> Result<Summary, Error> {
    let missing = results.missing();
    if let Some(first) = missing.first() {
        return Err(WriteError::Missing {
            count: missing.len(),
            first: *first,
        }
        .into());
    }
    let figs = opts.docs.join("figures");
    std::fs::create_dir_all(&figs)?;
    let main = opts.placement;
    let s = Scenes::new(main)?;
    let runs = run_files(&figs, results, &s)?;
    let [sweeps, other_sweeps] = sweep_files(&figs, main, results, &s)?;
    let [maps, other_maps] = map_files(&figs, main, results, &s)?;
    let [profile, other_profile] = profile_files(&figs, main, results, &s.cloud)?;
    let caption = caption_cloud::write(&figs, main, results)?;
    let courses = course_files(&figs, main, results, &s)?;
    let plateaus: Vec<(f64, f64, usize)> = courses
        .iter()
        .map(|[c, _]| (c.plateau, c.plateau_se, c.plateau_runs))
        .collect();
    let settled = settle::write(&figs, main, s.fields(), results, &courses, &caption)?;
    let cycle_rows = cycle_files(&figs, results.cycle(Unit::Cycle)?, &s.sharp)?;
    let sensitivity = sensitivity::write(&figs, main, &s.sharp, &s.gradient, results)?;
    let shapes = results.shapes(Unit::Shapes)?;
    crate::figures::write_shapes(&figs, shapes)?;
    let beyond = beyond::write(&figs, s.fields(), results)?;
    let waves = wave_files(&figs, results)?;
    let wall_s = results.wall_s();
    let (md, model) = markdown(&Report {
        placement: results.placements(Unit::Placements)?.clone(),
        speed: results.speed(Unit::Speed)?,
        peer_work_s: *results.peer_work(Unit::PeerWork)?,
        seed: opts.seed,
        wall_s,
        threads: results.threads(),
        sharp: &s.sharp,
        gradient: &s.gradient,
        cloud: &s.cloud,
        runs: &runs,
        sweeps: &sweeps,
        main,
        other_sweeps: &other_sweeps,
        maps: &maps,
        other_maps: &other_maps,
        profile,
        other_profile,
        profile_runs: PROFILE_RUNS,
        caption_cloud: &caption,
        plateaus: &plateaus,
        plateau_runs: COURSE_RUNS,
        courses: &courses,
        sensitivity: &sensitivity,
        shapes: &shapes.section,
        beyond: &beyond,
        settled: &settled,
        cycle_rows: &cycle_rows,
        cycle_runs: CYCLE_RUNS,
        waves,
    })?;
    let report = opts.docs.join("reproduction.md");
    std::fs::write(&report, md)?;
    let data = opts.docs.join("data");
    std::fs::create_dir_all(&data)?;
    let mut json = serde_json::to_string_pretty(&model)?;
    json.push('\n');
    std::fs::write(data.join(MODEL), json)?;
    Ok(Summary {
        report,
        wall_s,
        placement: main,
        sharp: sweeps[0].clone(),
        gradient: sweeps[1].clone(),
        sharp_other: other_sweeps[0].clone(),
        gradient_other: other_sweeps[1].clone(),
    })
}

/// Figs. 5 and 8: each run's CSV file and figure; the runs with their tries.
fn run_files(figs: &Path, results: &Results, s: &Scenes) -> Result<Vec<(u64, RunOutput)>, Error> {
    let mut runs = Vec::new();
    for f in Field::BOTH {
        let scn = s.field(f);
        let r = results.run(Unit::Run(f))?;
        write_run_csv(
            &figs.join(format!("{}-run.csv", scn.name)),
            &r.out,
            &scn.run,
        )?;
        figures::run_figure(&figs.join(format!("{}-run.svg", scn.name)), scn, &r.out)?;
        runs.push((r.tries, r.out.clone()));
    }
    Ok(runs)
}

/// Figs. 6 and 9: the sweeps' CSV files (`SCENARIO-sweep.csv` with the main placement,
/// `SCENARIO-sweep-OTHER.csv` with the other) and figures; the sweeps per placement (main,
/// other), per field.
fn sweep_files(
    figs: &Path,
    main: Placement,
    results: &Results,
    s: &Scenes,
) -> Result<[Vec<Vec<SweepPoint>>; 2], Error> {
    let mut out = [Vec::new(), Vec::new()];
    for f in Field::BOTH {
        for side in Side::BOTH {
            let pts = results.sweep(Unit::Sweep(f, side))?;
            let suffix = match side {
                Side::Main => String::new(),
                Side::Other => format!("-{}", placement(main, side)),
            };
            let csv = figs.join(format!("{}-sweep{suffix}.csv", s.field(f).name));
            write_sweep_csv(&csv, pts)?;
            out[side.index()].push(pts.clone());
        }
    }
    sweep_figures(figs, main, s.fields(), &out[0], &out[1])?;
    Ok(out)
}

/// The sweep figures: both placements and the paper's rates.
fn sweep_figures(
    figs: &Path,
    main: Placement,
    scns: [&Scenario; 2],
    sweeps: &[Vec<SweepPoint>],
    other_sweeps: &[Vec<SweepPoint>],
) -> Result<(), Error> {
    let [sharp, gradient] = scns;
    for (k, (scn, paper)) in [
        (sharp, marks::sweep_for("sharp")),
        (gradient, marks::sweep_for("gradient")),
    ]
    .into_iter()
    .enumerate()
    {
        // The scenario's own criterion, as `swarm sweep` prints it.
        let crit = scn
            .success
            .as_ref()
            .map_or_else(|| "no criterion".into(), |c| format!("{c} R"));
        figures::sweep_figure(
            &figs.join(format!("{}-sweep.svg", scn.name)),
            &format!(
                "{}: success ({crit} within {} periods), runs per point: {main} {}, {} {}",
                scn.name,
                scn.periods,
                sweeps[k].first().map_or(0, |p| p.runs),
                main.other(),
                other_sweeps[k].first().map_or(0, |p| p.runs),
            ),
            &[
                (format!("{main} placement").as_str(), &sweeps[k]),
                (
                    format!("{} placement", main.other()).as_str(),
                    &other_sweeps[k],
                ),
            ],
            &paper,
        )?;
    }
    Ok(())
}

/// Figs. 7, 10, 11: the direction maps' CSV files and figures (`NAME-field`, and with the other
/// placement `NAME-field-PLACEMENT`); the maps, per side (main, other).
fn map_files(
    figs: &Path,
    main: Placement,
    results: &Results,
    s: &Scenes,
) -> Result<[Vec<Vec<Arrow>>; 2], Error> {
    let mut maps = [Vec::new(), Vec::new()];
    for side in Side::BOTH {
        for (m, scn) in [
            (Scene::Sharp, &s.sharp),
            (Scene::Gradient, &s.gradient),
            (Scene::Cloud, &s.cloud),
        ] {
            let grid = scn.grid.as_ref().ok_or(WriteError::NoGrid)?;
            let arrows = results.map(Unit::Map(m, side))?;
            let name = match side {
                Side::Main => format!("{}-field", scn.name),
                Side::Other => format!("{}-field-{}", scn.name, main.other()),
            };
            write_field_csv(&figs.join(format!("{name}.csv")), arrows)?;
            figures::direction_figure(
                &figs.join(format!("{name}.svg")),
                scn,
                grid,
                arrows,
                &marks::map(&scn.name),
            )?;
            maps[side.index()].push(arrows.clone());
        }
    }
    Ok(maps)
}

/// Cloud: the radial profile's CSV file and figure (and the other placement's CSV file); the
/// profiles, main and other.
fn profile_files<'a>(
    figs: &Path,
    main: Placement,
    results: &'a Results,
    cloud: &Scenario,
) -> Result<[&'a [RadialPoint]; 2], Error> {
    let other = results.profile(Unit::CloudProfile(Side::Other))?;
    write_radial_csv(
        &figs.join(format!("cloud-profile-{}.csv", main.other())),
        other,
    )?;
    let profile = results.profile(Unit::CloudProfile(Side::Main))?;
    write_radial_csv(&figs.join("cloud-profile.csv"), profile)?;
    figures::radial_figure(
        &figs.join("cloud-profile.svg"),
        &format!(
            "cloud: heading of a swarm against its distance from the cloud's centre, {PROFILE_RUNS} runs per point"
        ),
        profile,
        &marks::profile_lines(cloud),
    )?;
    Ok([profile, other])
}

/// Figs. 5b and 8b averaged: per field, the courses' CSV file and figure; the courses
/// (`[main, other]` per field).
fn course_files(
    figs: &Path,
    main: Placement,
    results: &Results,
    s: &Scenes,
) -> Result<Vec<[TimeCourse; 2]>, Error> {
    let mut courses = Vec::new();
    for f in Field::BOTH {
        let scn = s.field(f);
        let m = results.course(Unit::Course(f, Side::Main))?.clone();
        let o = results.course(Unit::Course(f, Side::Other))?.clone();
        let (main_name, other_name) = (main.to_string(), main.other().to_string());
        let named = [(main_name.as_str(), &m), (other_name.as_str(), &o)];
        write_course_csv(&figs.join(format!("{}-course.csv", scn.name)), &named)?;
        time_course_figure(
            &figs.join(format!("{}-course.svg", scn.name)),
            &format!(
                "{}: {} runs from x = {} per placement, averaged",
                scn.name, COURSE_RUNS, scn.start.x
            ),
            &named,
            &marks::course(&scn.name),
        )?;
        courses.push([m, o]);
    }
    Ok(courses)
}

/// The cycle length: its CSV file and figure; the page's rows.
fn cycle_files(figs: &Path, runs: &[CycleRun], sharp: &Scenario) -> Result<Vec<CycleRow>, Error> {
    let rows: Vec<CycleRow> = runs
        .iter()
        .map(|r| CycleRow {
            cycle_s: r.cycle_s,
            waves_heard: r.waves_heard,
            initiating: r.initiating,
            agent_cycles: r.agent_cycles,
            points: r.points.clone(),
        })
        .collect();
    write_cycle_csv(&figs.join("cycle-effect.csv"), &rows)?;
    cycle_figure(&figs.join("cycle-effect.svg"), sharp, &rows)?;
    Ok(rows)
}

/// The cycle-length figure: success from each start and waves heard, against the cycle.
fn cycle_figure(path: &Path, sharp: &Scenario, cycle_rows: &[CycleRow]) -> Result<(), Error> {
    let lines: Vec<Line> = CYCLE_XS
        .iter()
        .enumerate()
        .map(|(i, &x)| Line {
            label: format!("success rate from x = {x}"),
            points: cycle_rows
                .iter()
                .map(|r| (r.cycle_s as f64, r.points[i].success_rate(), 0.0))
                .collect(),
        })
        .chain(std::iter::once(Line {
            label: format!("waves heard per agent per cycle / {}", sharp.agents),
            points: cycle_rows
                .iter()
                .map(|r| (r.cycle_s as f64, r.waves_heard / sharp.agents as f64, 0.0))
                .collect(),
        }))
        .chain(std::iter::once(Line {
            label: "agents that initiate a wave in the cycle".into(),
            points: cycle_rows
                .iter()
                .map(|r| (r.cycle_s as f64, r.initiating_share(), 0.0))
                .collect(),
        }))
        .collect();
    plot::xy_figure(
        path,
        &format!("sharp border: effect of the cycle length t_p^max ({CYCLE_RUNS} runs per point)"),
        "cycle length t_p^max / s",
        "fraction",
        &lines,
        (0.0, 1.05),
        &[],
        true,
    )?;
    Ok(())
}

/// Fig. 2: the wave's CSV file and figure; the page's section.
fn wave_files(figs: &Path, results: &Results) -> Result<crate::waves::WavesSection, Error> {
    crate::waves::write(figs, results.waves(Unit::Waves)?)
}
