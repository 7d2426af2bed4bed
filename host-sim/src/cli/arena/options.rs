//! What the options of `cimax arena` set, shared by a line and a plane: the robots' protocol
//! parameters, the light medium, the run's length and the robots in the loop, each checked.

use std::path::{Path, PathBuf};

use hal_emu::MediumParams;
use std::time::Duration as StdDuration;

use hal_emu::world::hil::{Follower, HilClock, HilRobot, HilSpec, HilTimeouts, Transport};
use lab::InTheLoop;
use protocol::{Duration, Params};

use super::{ArenaArgs, HilClockArg, MAX_RUN_SECS};

/// The robots in the loop in every run of a campaign or a sweep (`--hil`, `--hil-image`), for
/// runs of `most` robots with `sectors` receivers each, checked: only `qemu:N` and
/// `loopback:N` (on the arena's clock, which can reboot them), QEMU robots need their image.
pub(in crate::cli) fn in_the_loop(
    spec: Option<&HilSpec>,
    image: Option<&PathBuf>,
    sectors: u8,
    most: usize,
) -> Result<Option<InTheLoop>, String> {
    let Some(spec) = spec else {
        return Ok(None);
    };
    match spec {
        HilSpec::Qemu(n) | HilSpec::Loopback(n) if *n > most => Err(format!(
            "--hil: {n} robots in the loop, but the runs have {most} robots"
        )),
        HilSpec::Qemu(robots) => Ok(Some(InTheLoop {
            robots: *robots,
            image: Some(qemu_image(image, sectors)?),
        })),
        HilSpec::Loopback(robots) => Ok(Some(InTheLoop {
            robots: *robots,
            image: None,
        })),
        HilSpec::Serial(..) | HilSpec::Tcp(_) => Err(
            "--hil: robots in the loop of many runs are rebooted between them, so only qemu:N \
             and loopback:N (on the arena's clock) can take part, not a board or a socket"
                .into(),
        ),
    }
}

/// The image QEMU robots with `sectors` receivers boot: `image` (`--hil-image`) or the one
/// `cargo hil-image` builds; it must be there, and the HIL images have 2 or 6 receivers.
fn qemu_image(image: Option<&PathBuf>, sectors: u8) -> Result<PathBuf, String> {
    if sectors != 2 && sectors != 6 {
        return Err(format!(
            "--hil qemu: the HIL images have 2 (hil) or 6 (hil6) receivers, not {sectors}"
        ));
    }
    let image = image.cloned().unwrap_or_else(|| default_image(sectors));
    if !image.is_file() {
        return Err(format!(
            "--hil qemu: no image at {} (build it with `cargo hil-image`; docs/hil.md)",
            image.display()
        ));
    }
    Ok(image)
}

/// `--cycle` over the paper's 55 s (1 without `--cycle`).
pub(super) fn time_scale(args: &ArenaArgs) -> Result<f64, String> {
    let Some(c) = args.cycle else { return Ok(1.0) };
    secs(c, "cycle")?;
    Ok(c / Params::robots().wave.cycle.as_secs_f64())
}

/// `d` times `scale`, to the millisecond, at least 1 ms.
pub(super) fn scaled(d: Duration, scale: f64) -> Duration {
    Duration::from_millis(((d.as_millis() as f64 * scale).round() as u64).max(1))
}

/// The robots in the loop the options ask for, in a swarm of `robots` with `sectors` each:
/// their places (`--hil-at`, else the first ones) and transports.
pub(super) fn hil_robots(
    args: &ArenaArgs,
    robots: usize,
    sectors: u8,
) -> Result<Vec<HilRobot>, String> {
    if args.hil.is_empty() {
        return Ok(Vec::new());
    }
    let image = args
        .hil_image
        .clone()
        .unwrap_or_else(|| default_image(sectors));
    let transports: Vec<Transport> = args.hil.iter().flat_map(|h| h.transports(&image)).collect();
    if transports.iter().any(|t| matches!(t, Transport::Qemu(_))) {
        qemu_image(Some(&image), sectors)?;
    }
    let places: Vec<usize> = if args.hil_at.is_empty() {
        (0..transports.len()).collect()
    } else if args.hil_at.len() == transports.len() {
        args.hil_at.clone()
    } else {
        return Err(format!(
            "--hil-at names {} places for {} robots in the loop",
            args.hil_at.len(),
            transports.len()
        ));
    };
    if transports.len() > robots {
        return Err(format!(
            "{} robots in the loop, but only {robots} places",
            transports.len()
        ));
    }
    if let Some(p) = places.iter().find(|&&p| p >= robots) {
        return Err(format!(
            "--hil-at {p}: there is no place {p} (robots are 0..{})",
            robots - 1
        ));
    }
    let robots: Vec<HilRobot> = places
        .into_iter()
        .zip(transports)
        .map(|(robot, transport)| {
            Ok(HilRobot {
                robot,
                clock: hil_clock(args, &transport)?,
                transport,
            })
        })
        .collect::<Result<_, String>>()?;
    if args.key.is_some()
        && let Some(r) = robots.iter().find(|r| r.clock == HilClock::Wall)
    {
        return Err(format!(
            "--key with --hil {} on its own clock: link version 3 gives the swarm key only to \
             robots on the arena's clock (--hil-clock virtual: qemu, loopback, or a socket \
             robot that can follow)",
            r.transport
        ));
    }
    Ok(robots)
}

/// The clock a robot in the loop over `t` runs on: `--hil-clock`, or the transport's default
/// (docs/hil.md, "Time"): the arena's for QEMU and loopback, its own for a board on a serial
/// port, and for one on a socket the one its `Hello` says it can follow.
fn hil_clock(args: &ArenaArgs, t: &Transport) -> Result<HilClock, String> {
    match (args.hil_clock, t) {
        (Some(HilClockArg::Virtual) | None, Transport::Qemu(_) | Transport::InProcess) => {
            Ok(HilClock::Virtual)
        }
        (Some(HilClockArg::Wall), Transport::InProcess) => Err(
            "--hil-clock wall with loopback: the robot in this process runs on the arena's \
             clock"
                .into(),
        ),
        (Some(HilClockArg::Virtual), Transport::Serial(..)) => Err(format!(
            "--hil-clock virtual with {t}: a board on a serial port keeps its own time \
             (its image cannot follow the arena's clock); use --hil-clock wall"
        )),
        (Some(HilClockArg::Virtual), Transport::Tcp(_)) => Ok(HilClock::Virtual),
        (None, Transport::Tcp(addr)) => {
            // Its Hello says which (it is asked once, before the run).
            let hello = HilTimeouts::default().hello.as_millis();
            let follows = Follower::follows_host_clock(addr, StdDuration::from_millis(hello))
                .map_err(|e| format!("--hil {t}: {e}"))?;
            Ok(if follows {
                HilClock::Virtual
            } else {
                HilClock::Wall
            })
        }
        (Some(HilClockArg::Wall), _) | (None, _) => Ok(HilClock::Wall),
    }
}

/// Checks `--kill` and `--restart` (ROBOT@SECONDS each): per robot, kills and restarts
/// alternate in time, a kill first: no restart of a robot alive then, no kill of a robot
/// already dead, no option given twice.
pub(super) fn check_kills(kills: &[(usize, u64)], restarts: &[(usize, u64)]) -> Result<(), String> {
    let mut events: Vec<(usize, u64, bool)> = kills
        .iter()
        .map(|&(r, t)| (r, t, true))
        .chain(restarts.iter().map(|&(r, t)| (r, t, false)))
        .collect();
    let name = |kill: bool| if kill { "--kill" } else { "--restart" };
    for (i, &(r, t, kill)) in events.iter().enumerate() {
        if events[..i].contains(&(r, t, kill)) {
            return Err(format!("{} {r}@{t} is given twice", name(kill)));
        }
    }
    // In time order per robot; at one time a kill before a restart.
    events.sort_by_key(|&(r, t, kill)| (r, t, !kill));
    let mut last: Option<(usize, u64, bool)> = None;
    for &(r, t, kill) in &events {
        let before = last.filter(|&(lr, _, _)| lr == r);
        match (kill, before) {
            (true, Some((_, lt, true))) => {
                return Err(format!(
                    "--kill {r}@{t}: robot {r} is already dead then (--kill {r}@{lt}, no --restart between)"
                ));
            }
            (false, None | Some((_, _, false))) => {
                return Err(format!(
                    "--restart {r}@{t}: robot {r} is alive then (a restart follows a --kill of it)"
                ));
            }
            (false, Some((_, lt, true))) if lt == t => {
                return Err(format!(
                    "--restart {r}@{t}: at the time of its --kill {r}@{lt}; restart it later"
                ));
            }
            _ => {}
        }
        last = Some((r, t, kill));
    }
    Ok(())
}

/// Where `cargo hil-image` puts the HIL images, in the workspace.
const IMAGE_DIR: &str = "firmware/qemu/target/thumbv7em-none-eabihf/release";

/// The image `--hil qemu:N` boots without `--hil-image`: `hil` (2 sectors) or `hil6`, under
/// [`IMAGE_DIR`] of the working folder if it is there, else of the checkout this `cimax` was
/// built from (as the docs folder is found, [`report::default_docs_dir`]).
pub(in crate::cli) fn default_image(sectors: u8) -> PathBuf {
    let name = if sectors == 2 { "hil" } else { "hil6" };
    let here = PathBuf::from(IMAGE_DIR).join(name);
    if here.is_file() {
        return here;
    }
    let checkout = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let checkout = checkout.canonicalize().unwrap_or(checkout);
    checkout.join(IMAGE_DIR).join(name)
}

/// `s` seconds as a [`Duration`], to the millisecond; an error naming `--what` unless it is a
/// non-negative number.
pub(super) fn secs(s: f64, what: &str) -> Result<Duration, String> {
    if s.is_finite() && s >= 0.0 {
        Ok(Duration::from_millis((s * 1000.0).round() as u64))
    } else {
        Err(format!(
            "--{what} must be a non-negative number of seconds, not {s}"
        ))
    }
}

/// The light medium the options describe.
pub(super) fn medium(args: &ArenaArgs) -> Result<MediumParams, String> {
    let medium = MediumParams {
        bitrate: args.bitrate,
        range: args.range,
        loss: args.loss,
        byte_error_rate: args.byte_error_rate,
        collisions: !args.no_collisions,
        ..MediumParams::default()
    };
    medium.validate().map_err(|e| e.to_string())?;
    Ok(medium)
}

/// The robots' protocol parameters: `Params::robots()` with the options' changes, validated.
pub(super) fn robot_params(args: &ArenaArgs) -> Result<Params, String> {
    let mut params = Params::robots();
    if let Some(c) = args.cycle {
        // The timing the options leave out keeps the paper's proportions to the cycle
        // (15 s spread, 1 s relay delay and 4 s refractory to 55 s), so that `--cycle 2`
        // alone shrinks a whole run (robots in the loop run in real time).
        let scale = time_scale(args)?;
        let w = &mut params.wave;
        w.cycle = secs(c, "cycle")?;
        w.cycle_spread = scaled(w.cycle_spread, scale);
        w.relay_delay = scaled(w.relay_delay, scale);
        w.refractory = scaled(w.refractory, scale);
    }
    if let Some(c) = args.cycle_spread {
        params.wave.cycle_spread = secs(c, "cycle-spread")?;
    }
    if let Some(r) = args.refractory {
        params.wave.refractory = secs(r, "refractory")?;
    }
    if let Some(n) = args.negotiation {
        params.negotiation_cycles = n;
    }
    params.decide = args.decide.into();
    params
        .validate()
        .map_err(|e| format!("protocol parameters: {e}"))?;
    Ok(params)
}

/// The length of a run (`--duration`, or three negotiation periods of the longest cycle),
/// after checking `--spacing`.
pub(super) fn run_length(args: &ArenaArgs, params: &Params) -> Result<Duration, String> {
    if !(args.spacing.is_finite() && args.spacing > 0.0) {
        return Err(format!(
            "--spacing must be a positive number of metres, not {}",
            args.spacing
        ));
    }
    let run = args.duration.map_or(params.lab_run(), Duration::from_secs);
    if run > Duration::from_secs(MAX_RUN_SECS) {
        return Err(format!(
            "a run of three negotiation periods of the longest cycle (--cycle, --cycle-spread, \
             --negotiation) lasts {} s; at most {MAX_RUN_SECS} s (give a --duration)",
            run.as_millis().div_ceil(1000)
        ));
    }

    Ok(run)
}
