//! The QEMU board: `qemu-system-arm -machine mps2-an386` (Cortex-M4).
//!
//! Four virtual robots in a line run the unchanged robot program ([`firmware::Robot::run`]) in
//! one image, wired in memory ([`firmware::wired::run_line`]) under a lamp pattern, on
//! embassy-time driven by a small tickless SysTick time driver ([`systick`]). Each robot logs
//! its decisions over semihosting; when every robot has decided twice, the image compares what
//! the LEDs show with the paper's expected decisions, prints the verdict and exits through
//! semihosting: status 0 if every decision is right, 1 if one is wrong or missing (deadline:
//! three negotiation periods). Two patterns run one after the other: `1000` and `1100`.
//!
//! Then the recovery check (issue 14: a deployed robot must come back by itself). The image
//! panics on purpose; its panic handler resets the board, as the Nucleo's release image does;
//! after the reset the robots run and decide again. Then the board's watchdog (the CMSDK APB
//! watchdog, [`watchdog`], standing in for the Nucleo's IWDG) is fed by every round of the
//! robots' main loops ([`Observer::progress`]), until one robot's loop gets stuck: the
//! watchdog resets the board, and the robots run and decide once more. A record in `.uninit`
//! RAM ([`boot`]) carries the stage and the verdict across the resets; any reset the stage did
//! not expect ends the run with status 1 (with feeding switched off, the healthy run after the
//! panic is reset by the watchdog and the run fails).
//!
//! Run with `-icount shift=0,sleep=off`: the executor below sleeps in `WFI` and SysTick only
//! interrupts when a timer is due, so QEMU skips the idle time and the ~37 virtual minutes take
//! about a second, identically every run. Without `-icount` it runs in wall-clock time.
//!
//! Build and run from the repository root with `cargo qemu` (see `docs/firmware.md`), which is
//! `cargo run --manifest-path firmware/qemu/Cargo.toml --release --target thumbv7em-none-eabihf`
//! with `firmware/qemu/run.sh` as the runner.

#![no_std]
#![no_main]
#![deny(unsafe_code)]

use boot::Stage;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use exec::block_on;
use firmware::hal::EmbassyClock;
use firmware::protocol::lab::LabPattern;
use firmware::protocol::{Duration, Event, Instant, Level, Sector};
use firmware::wired::{run_line_observed, total_stats};
use firmware::{Clock, Config, LedColor, Observer, Robot};
use rand_pcg::Pcg32;

mod boot;
mod exec;
mod semilog;
mod systick;
mod watchdog;

/// The seed of every random draw; `CIMAX_SEED=n cargo qemu` replays another run.
const DEFAULT_SEED: u64 = 1;

/// The lamp patterns run one after the other (1 = lit), with the paper's decisions.
const SCENARIOS: [LabPattern; 2] = [paper("1000"), paper("1100")];

/// The paper's lab run of pattern `lights` ([`firmware::protocol::lab::PAPER`]); a pattern
/// that is not one of its six does not compile.
const fn paper(lights: &str) -> LabPattern {
    match LabPattern::find(lights) {
        Some(p) => p,
        None => panic!("not one of the paper's lab patterns"),
    }
}

/// Ends the QEMU run with status 0 (`ok`) or 1.
fn exit(ok: bool) -> ! {
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    // Only reached without semihosting (e.g. on a real Cortex-M4).
    loop {
        cortex_m::asm::wfi();
    }
}

/// As the Nucleo's release image does, a panic resets the board (after saying why, which the
/// Nucleo image leaves out to save flash). The boot record tells the next boot whether the
/// panic was the recovery check's or a real failure.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("PANIC: {}", info);
    let (stage, ok) = boot::load();
    match stage {
        Stage::PanicExpected => boot::store(Stage::AfterPanic, ok),
        _ => boot::store(Stage::Unexpected, false),
    }
    hprintln!("resetting the board");
    cortex_m::peripheral::SCB::sys_reset()
}

/// What each robot's main loop tells the board ([`Observer::progress`]): every round feeds
/// the watchdog, and with `hang_after = Some(n)` the `n`-th round spins for ever instead, as
/// a driver stuck waiting for a flag would, so that nothing feeds the watchdog any more.
#[derive(Clone, Copy, Default)]
struct Feeder {
    rounds: u32,
    hang_after: Option<u32>,
}

impl Observer for Feeder {
    fn event(&mut self, _: Instant, _: &Event) {}

    fn progress(&mut self, _: Instant) {
        self.rounds += 1;
        if self.hang_after.is_some_and(|n| self.rounds >= n) {
            hprintln!(
                "robot main loop stuck (round {}): no more feeding",
                self.rounds
            );
            loop {
                cortex_m::asm::wfi();
            }
        }
        watchdog::feed();
    }
}

/// The watchdog's timeout: 2 s of virtual time (the robots' loops come round every second;
/// the reset comes one or two timeouts after the last feed).
const WATCHDOG_CYCLES: u32 = 2 * watchdog::HZ;

// ---------------------------------------------------------------------------------------------

fn seed() -> u64 {
    option_env!("CIMAX_SEED")
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_SEED)
}

/// What the LEDs of a line show, as letters: `G` green (left), `B` blue (right), `-` off.
fn letters(decisions: [Option<Sector>; 4]) -> [u8; 4] {
    decisions.map(|d| match LedColor::for_decision(d) {
        LedColor::Green => b'G',
        LedColor::Blue => b'B',
        LedColor::Off => b'-',
        // Robots in a line have two sectors: never shown.
        LedColor::Sector(_) => b'?',
    })
}

/// Runs one pattern until every robot has decided twice (lit robots read 1, dark ones 0); true
/// if every LED shows the paper's decision.
async fn scenario(lab: &LabPattern, seed: u64, mut feeders: [Feeder; 4]) -> bool {
    let (pattern, expected) = (lab.lights, lab.expected());
    let clock = EmbassyClock;
    let start = clock.now();
    let make = |id: u16| {
        let config = Config {
            id,
            ..Config::robots()
        };
        Robot::new(config, start, Pcg32::new(seed, 2 * u64::from(id) + 1))
    };
    let (Ok(a), Ok(b), Ok(c), Ok(d)) = (make(0), make(1), make(2), make(3)) else {
        hprintln!("FAIL {}: bad configuration", pattern);
        return false;
    };
    let mut robots = [a, b, c, d];
    hprintln!("pattern {} (1 = lit), robots 0..3 left to right", pattern);
    // Two decisions need at most 2 x 10 cycles of 70 s; allow a third period.
    let deadline = start + Duration::from_secs(3 * 10 * 70);
    let report = run_line_observed(
        &mut robots,
        &mut feeders,
        lab.levels(Level(1), Level(0)),
        &clock,
        2,
        deadline,
    )
    .await;
    let got = report.shown_decisions();
    let s = total_stats(&robots);
    let ok = report.finished && got == expected;
    hprintln!(
        "{} {}: LEDs {}, expected {}, after {} s ({} decisions, {} frames sent, {} received, {} corrupt, {} bytes lost)",
        if ok { "RIGHT" } else { "WRONG" },
        pattern,
        core::str::from_utf8(&letters(got)).unwrap_or("?"),
        core::str::from_utf8(&letters(expected)).unwrap_or("?"),
        report.at.saturating_since(start).as_millis() / 1000,
        s.decisions,
        s.transmitted,
        s.messages,
        s.frame_errors,
        report.lost.iter().sum::<u32>(),
    );
    if !report.finished {
        hprintln!(
            "  not every robot decided twice before the deadline: {:?}",
            report.decisions
        );
    }
    ok
}

/// Frames whose decoding the host's tests pin (`protocol::frame::tests`, docs/protocol.md
/// §2.3, §2.4), decoded here on the Cortex-M with the same expected results: host and robot
/// decode every frame alike (no limit depends on the word size).
fn decoding_matches_the_host() -> bool {
    use firmware::protocol::FrameError::{TooLong, Undecodable};
    use firmware::protocol::{Deframer, Hop, Message, Tag};
    // GOLDEN_ONE_HOP: reading 1, no preference, tag 0.
    const ONE_HOP: &[u8] = b"ss\x70\x32\x72\x70\x43\xa6ss";
    // The overlong hop count (format 1's count 1 in 6 varint bytes): undecodable.
    const OVERLONG: &[u8] = b"ss\x75\xf2\xf3\xf3\xf3\xf3\x71\x72\x70\x1f\x4b\x73\x73";
    // GOLDEN_TAGGED_TWELVE with byte 30 (its closing delimiter's first `s`) corrupted.
    const TWELVE_CUT: &[u8] = b"ss\x6f\x3f\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x92\x99\x00s";
    let one_hop = Message::from_hops(&[Hop {
        reading: Level(1),
        pref: None,
        tag: Tag::from_id(0),
    }]);
    let mut d = Deframer::new();
    let mut got: [Option<Result<Message, firmware::protocol::FrameError>>; 4] =
        [None, None, None, None];
    let mut n = 0;
    for chunk in [OVERLONG, ONE_HOP, TWELVE_CUT, ONE_HOP] {
        for r in d.frames(chunk) {
            if let Some(slot) = got.get_mut(n) {
                *slot = Some(r);
            }
            n += 1;
        }
    }
    let ok = n == 4
        && got[0] == Some(Err(Undecodable))
        && got[1] == one_hop.clone().map(Ok)
        && got[2] == Some(Err(TooLong))
        && got[3] == one_hop.map(Ok);
    hprintln!(
        "decoding on the Cortex-M: {} (overlong count undecodable, cut delimiter too long, the frames after decoded)",
        if ok {
            "as on the host"
        } else {
            "DIFFERS from the host"
        }
    );
    ok
}

/// The recovery check after a reset the board asked for: the robots run again and decide.
fn after_reset(why: &str, lab: &LabPattern, seed: u64) -> bool {
    hprintln!("came back after {}: the robots run again", why);
    watchdog::start(WATCHDOG_CYCLES);
    block_on(scenario(lab, seed, [Feeder::default(); 4]))
}

#[entry]
fn main() -> ! {
    let Some(cp) = cortex_m::Peripherals::take() else {
        exit(false)
    };
    systick::init(cp.SYST);
    semilog::init();

    let seed = seed();
    let (stage, ok_before) = boot::load();
    // Until a stage says which reset it expects next, any reset is a failure (and not a loop:
    // the next boot ends the run).
    boot::store(Stage::Unexpected, false);
    match stage {
        Stage::Cold => {
            hprintln!(
                "cimax qemu: 4 robots in a line, seed {} (CIMAX_SEED to replay)",
                seed
            );
            let mut all_right = decoding_matches_the_host();
            for lab in &SCENARIOS {
                all_right &= block_on(scenario(lab, seed, [Feeder::default(); 4]));
            }
            // Recovery, part 1: a panic resets the board (the panic handler above).
            boot::store(Stage::PanicExpected, all_right);
            hprintln!("recovery check: a forced panic must reset the board");
            panic!("forced (the recovery check)");
        }
        Stage::AfterPanic => {
            let all_right = ok_before && after_reset("the panic", &paper("1000"), seed);
            // Recovery, part 2: a robot whose main loop stops is reset by the watchdog, which
            // every robot fed on each round until now.
            boot::store(Stage::HangExpected, all_right);
            hprintln!("recovery check: a stuck main loop must be reset by the watchdog");
            let mut feeders = [Feeder::default(); 4];
            feeders[1].hang_after = Some(30);
            watchdog::start(WATCHDOG_CYCLES);
            let decided = block_on(scenario(&paper("1000"), seed, feeders));
            // Only reached if the hang did not happen.
            hprintln!(
                "FAIL: the main loop was meant to hang (decided: {})",
                decided
            );
            boot::clear();
            exit(false)
        }
        Stage::HangExpected => {
            let all_right = ok_before && after_reset("the watchdog reset", &paper("1100"), seed);
            boot::clear();
            if all_right {
                hprintln!(
                    "PASS: every robot decided as the paper says, also after a panic and a watchdog reset"
                );
            } else {
                hprintln!("FAIL: a decision was wrong or missing");
            }
            exit(all_right)
        }
        Stage::PanicExpected | Stage::Unexpected => {
            hprintln!("FAIL: an unexpected reset or panic (stage {:?})", stage);
            boot::clear();
            exit(false)
        }
    }
}
