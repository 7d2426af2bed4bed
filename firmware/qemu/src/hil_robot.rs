//! What the QEMU board's HIL images share (`bin/hil.rs`, two receivers like the lab's robots;
//! `bin/hil6.rs`, six like the paper's 2D agents): the robot in the loop, the unchanged robot
//! program ([`firmware::Robot::run`]) over the link of `docs/hil.md` on UART0 ([`uart`]), in
//! wall-clock time (a 1 kHz SysTick, [`tick`]; run without `-icount`), or on the host's
//! clock when its `Setup` asks (no SysTick: the host's `Sync`s move the time). It joins the emulated
//! arena: `cimax arena --hil qemu:N` starts one QEMU process per robot, its UART0 a TCP client
//! of the host (`hal_emu::world::hil::qemu_args`); its semihosting log goes to QEMU's stdout.
//!
//! It says `Hello` until the host sends its `Setup`, then runs the robot with the setup's id,
//! seed and timing; each new `Setup` restarts it afresh. A panic resets the board (the host
//! sees a second `Hello` and fails the run, naming the robot).

use cortex_m_rt::exception;
use cortex_m_semihosting::hprintln;
use firmware::Config;
use firmware::hal::EmbassyClock;
use firmware::hil::robot::{Link, RNG_STREAM, run};
use rand_pcg::Pcg32;

use crate::{exec, semilog, tick, uart};

/// The robot's id before the host gives it one (its `Hello` says it).
const ID: u16 = 0;

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

/// Runs the robot in the loop with `N` receivers, for ever.
pub fn main<const N: usize>() -> ! {
    let Some(cp) = cortex_m::Peripherals::take() else {
        panic!("peripherals taken twice")
    };
    tick::init(cp.SYST);
    semilog::init();
    let (tx, rx) = uart::init();
    hprintln!(
        "cimax hil: one robot with {} receivers on UART0, waiting for the host's setup",
        N
    );
    // Its clock follows the host's when a `Setup` asks (docs/hil.md, "Time").
    let link = Link::<_, N>::with_host_clock(tx, tick::HOST_CLOCK);
    let base = Config {
        id: ID,
        ..Config::robots()
    };
    let mut observer = ();
    let robot = run(
        &link,
        rx,
        &EmbassyClock,
        base,
        |seed| Pcg32::new(u64::from(seed), RNG_STREAM),
        &mut observer,
    );
    // Nothing to run and no byte waiting to go: an `Idle` owed to the host can be sent.
    let idle = || {
        if !uart::tx_busy() {
            link.on_idle();
        }
    };
    match exec::block_on_idle(robot, idle) {}
}
