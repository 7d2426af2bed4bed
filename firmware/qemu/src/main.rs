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

use core::future::Future;
use core::pin::pin;
use core::sync::atomic::{AtomicBool, Ordering};
use core::task::{Context, Poll, RawWaker, RawWakerVTable, Waker};

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use firmware::hal::EmbassyClock;
use firmware::protocol::{Duration, Level, Sector};
use firmware::wired::{run_line, total_stats};
use firmware::{Clock, Config, LedColor, Robot};
use rand_pcg::Pcg32;

mod systick;

/// The seed of every random draw; `CIMAX_SEED=n cargo qemu` replays another run.
const DEFAULT_SEED: u64 = 1;

const L: Option<Sector> = Some(Sector::LEFT);
const R: Option<Sector> = Some(Sector::RIGHT);

/// The lamp patterns run one after the other (1 = lit), with the paper's decisions.
const SCENARIOS: [(&str, [Option<Sector>; 4]); 2] =
    [("1000", [L, L, L, L]), ("1100", [R, R, L, L])];

// ---------------------------------------------------------------------------------------------
// A tiny executor: polls one future when it was woken, sleeps in WFI otherwise (which lets QEMU's
// `-icount sleep=off` jump straight to the next interrupt).

static WOKEN: AtomicBool = AtomicBool::new(true);

fn wake(_: *const ()) {
    WOKEN.store(true, Ordering::Release);
}

fn clone(data: *const ()) -> RawWaker {
    RawWaker::new(data, &VTABLE)
}

fn drop(_: *const ()) {}

static VTABLE: RawWakerVTable = RawWakerVTable::new(clone, wake, wake, drop);

fn block_on<F: Future>(future: F) -> F::Output {
    let mut future = pin!(future);
    #[allow(unsafe_code)]
    // SAFETY: the vtable's functions ignore the (null) data pointer and only touch an atomic,
    // so the RawWaker contract (thread-safe, clone gives an equivalent waker) holds.
    let waker = unsafe { Waker::from_raw(RawWaker::new(core::ptr::null(), &VTABLE)) };
    let mut cx = Context::from_waker(&waker);
    loop {
        if WOKEN.swap(false, Ordering::AcqRel) {
            if let Poll::Ready(out) = future.as_mut().poll(&mut cx) {
                return out;
            }
        } else {
            // Interrupts masked between the check and WFI, so a wake-up cannot slip in between;
            // WFI still returns on a pending interrupt, which runs once they are unmasked.
            cortex_m::interrupt::free(|_| {
                if !WOKEN.load(Ordering::Acquire) {
                    cortex_m::asm::wfi();
                }
            });
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Logging over semihosting, stamped with virtual time.

struct SemihostingLogger;

impl log::Log for SemihostingLogger {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Info
    }

    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            let t = EmbassyClock.now().as_millis();
            hprintln!(
                "[{:>5}.{:03}] {:<5} {}",
                t / 1000,
                t % 1000,
                record.level(),
                record.args()
            );
        }
    }

    fn flush(&self) {}
}

static LOGGER: SemihostingLogger = SemihostingLogger;

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

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("PANIC: {}", info);
    exit(false)
}

// ---------------------------------------------------------------------------------------------

fn readings(pattern: &str) -> [Level; 4] {
    let b = pattern.as_bytes();
    core::array::from_fn(|i| Level(u8::from(b.get(i) == Some(&b'1'))))
}

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

/// Runs one pattern until every robot has decided twice; true if every LED shows the expected
/// decision.
async fn scenario(pattern: &str, expected: [Option<Sector>; 4], seed: u64) -> bool {
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
    let report = run_line(&mut robots, readings(pattern), &clock, 2, deadline).await;
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
    const ONE_HOP: &[u8] = b"ss\x70\x52\x72\x70\x28\x3dss";
    // The overlong hop count (format 1's count 1 in 6 varint bytes): undecodable.
    const OVERLONG: &[u8] = b"ss\x75\xf2\xf3\xf3\xf3\xf3\x71\x72\x70\x1f\x4b\x73\x73";
    // GOLDEN_TAGGED_TWELVE with byte 30 (its closing delimiter's first `s`) corrupted.
    const TWELVE_CUT: &[u8] = b"ss\x6f\x5f\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x8c\x8b\x0a\xc1\x00s";
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

#[entry]
fn main() -> ! {
    let Some(cp) = cortex_m::Peripherals::take() else {
        exit(false)
    };
    systick::init(cp.SYST);
    // Only fails if a logger is already set, and nothing else sets one.
    let _ = log::set_logger(&LOGGER).map(|()| log::set_max_level(log::LevelFilter::Info));

    let seed = seed();
    hprintln!(
        "cimax qemu: 4 robots in a line, seed {} (CIMAX_SEED to replay)",
        seed
    );
    let mut all_right = decoding_matches_the_host();
    for (pattern, expected) in SCENARIOS {
        all_right &= block_on(scenario(pattern, expected, seed));
    }
    if all_right {
        hprintln!("PASS: every robot decided as the paper says");
    } else {
        hprintln!("FAIL: a decision was wrong or missing");
    }
    exit(all_right)
}
