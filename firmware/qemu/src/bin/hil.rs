//! The QEMU board's robot in the loop: one robot, the unchanged robot program
//! ([`firmware::Robot::run`]) over the link of `docs/hil.md` on UART0 ([`uart`]), in wall-clock
//! time (a 1 kHz SysTick, [`tick`]; run without `-icount`). It joins the emulated arena:
//! `cimax arena --hil qemu:N` starts one QEMU process per robot, its UART0 a TCP client of
//! the host (`hal_emu::hil::qemu_args`); its semihosting log goes to QEMU's stdout.
//!
//! It says `Hello` until the host sends its `Setup`, then runs the robot with the setup's id,
//! seed and timing; each new `Setup` restarts it afresh. A panic resets the board (the host
//! sees a second `Hello` and fails the run, naming the robot). Logs go over semihosting.
//!
//! Build with `cargo hil-image` (from the repository root): the ELF is
//! `firmware/qemu/target/thumbv7em-none-eabihf/release/hil`.

#![no_std]
#![no_main]
#![deny(unsafe_code)]

use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::hprintln;
use firmware::hal::EmbassyClock;
use firmware::hil::robot::{Link, RNG_STREAM, run};
use firmware::{Clock, Config};
use rand_pcg::Pcg32;

#[path = "../exec.rs"]
mod exec;
#[path = "../tick.rs"]
mod tick;
#[path = "../uart.rs"]
mod uart;

/// The robot's id before the host gives it one (its `Hello` says it).
const ID: u16 = 0;

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

#[allow(unsafe_code)] // cortex-m-rt requires the default handler to be an `unsafe fn`.
#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    uart::on_interrupt(irqn);
}

/// As a deployed robot does, a panic resets the board.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("PANIC: {}", info);
    cortex_m::peripheral::SCB::sys_reset()
}

#[entry]
fn main() -> ! {
    let Some(cp) = cortex_m::Peripherals::take() else {
        panic!("peripherals taken twice")
    };
    tick::init(cp.SYST);
    let _ = log::set_logger(&LOGGER).map(|()| log::set_max_level(log::LevelFilter::Info));
    let (tx, rx) = uart::init();
    hprintln!("cimax hil: one robot on UART0, waiting for the host's setup");
    let link = Link::<_, 2>::new(tx);
    let base = Config {
        id: ID,
        ..Config::robots()
    };
    match exec::block_on(run(&link, rx, &EmbassyClock, base, |seed| {
        Pcg32::new(u64::from(seed), RNG_STREAM)
    })) {}
}
