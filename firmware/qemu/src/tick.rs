//! A periodic SysTick time driver for embassy-time: one interrupt per millisecond (embassy's
//! tick), `now` counts them; or, for a robot on the host's clock (link version 2, docs/hil.md
//! "Time"), no interrupt at all: `now` is what the host's last `Sync` said ([`HOST_CLOCK`]), and
//! a guest that waits in WFI costs QEMU nothing until the host writes. The HIL image runs in wall-clock time (no `-icount`), where the
//! tickless driver ([`super::systick`], for the four-robot check under `-icount`) misreads the
//! time: QEMU leaves the counter at zero for a moment after each restart, which the tickless
//! driver reads as a whole period gone, and the robot's clock ran 50 to 100 times too fast
//! under a busy link. Counting wraps of a fixed period never reads the counter.

use core::cell::RefCell;
use core::task::Waker;

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::exception;
use critical_section::Mutex;
use embassy_time_queue_utils::queue_generic::ConstGenericQueue;

/// mps2-an386 clocks its Cortex-M4 (and SysTick) at 25 MHz.
const SYSCLK_HZ: u32 = 25_000_000;
/// CPU cycles per embassy-time tick (`tick-hz-1_000` in Cargo.toml).
const CYCLES_PER_TICK: u32 = SYSCLK_HZ / embassy_time_driver::TICK_HZ as u32;

struct State {
    ticks: u64,
    next_alarm: u64,
    queue: ConstGenericQueue<8>,
    /// On the host's clock: SysTick is off and `ticks` moves only at `set_now`.
    following: bool,
}

static STATE: Mutex<RefCell<State>> = Mutex::new(RefCell::new(State {
    ticks: 0,
    next_alarm: u64::MAX,
    queue: ConstGenericQueue::new(),
    following: false,
}));

/// The hooks of `firmware::hil::robot::Link::with_host_clock`.
pub const HOST_CLOCK: firmware::hil::robot::HostClock = firmware::hil::robot::HostClock {
    follow,
    set_now,
    next_alarm,
};

/// The SysTick's registers (the driver owns them once [`init`] took them).
fn syst() -> &'static cortex_m::peripheral::syst::RegisterBlock {
    #[allow(unsafe_code)]
    // SAFETY: SYST::PTR is the core's SysTick block, always mapped; after `init` only this
    // module touches it, from critical sections or with interrupts masked.
    unsafe {
        &*SYST::PTR
    }
}

/// Follows the host's clock (`true`: SysTick stops, the time is 0 and every timer is
/// forgotten: a new run) or counts its own milliseconds again (`false`).
fn follow(on: bool) {
    critical_section::with(|cs| {
        let mut s = STATE.borrow_ref_mut(cs);
        let ctrl = syst().csr.read();
        const ENABLE_AND_INTERRUPT: u32 = 0b011;
        #[allow(unsafe_code)]
        // SAFETY: setting or clearing ENABLE and TICKINT of SysTick's CSR only starts or stops
        // this driver's own interrupt.
        unsafe {
            if on {
                syst().csr.write(ctrl & !ENABLE_AND_INTERRUPT);
            } else {
                syst().csr.write(ctrl | ENABLE_AND_INTERRUPT);
            }
        }
        if on {
            s.ticks = 0;
            s.queue = ConstGenericQueue::new();
            s.next_alarm = u64::MAX;
        }
        s.following = on;
    });
}

/// The host says the time is `ms`: every timer due by then wakes.
fn set_now(ms: u64) {
    critical_section::with(|cs| {
        let mut s = STATE.borrow_ref_mut(cs);
        s.ticks = s.ticks.max(ms);
        if s.ticks >= s.next_alarm {
            let now = s.ticks;
            s.next_alarm = s.queue.next_expiration(now);
        }
    });
}

/// The next timer set, milliseconds (`u64::MAX`: none).
fn next_alarm() -> u64 {
    critical_section::with(|cs| STATE.borrow_ref(cs).next_alarm)
}

/// Starts the clock at zero; call once, before anything asks for the time.
pub fn init(mut syst: SYST) {
    syst.disable_counter();
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(CYCLES_PER_TICK - 1);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

#[exception]
fn SysTick() {
    critical_section::with(|cs| {
        let mut s = STATE.borrow_ref_mut(cs);
        if s.following {
            return;
        }
        s.ticks += 1;
        if s.ticks >= s.next_alarm {
            let now = s.ticks;
            s.next_alarm = s.queue.next_expiration(now);
        }
    });
}

struct TickDriver;

impl embassy_time_driver::Driver for TickDriver {
    fn now(&self) -> u64 {
        critical_section::with(|cs| STATE.borrow_ref(cs).ticks)
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            let mut s = STATE.borrow_ref_mut(cs);
            if s.queue.schedule_wake(at, waker) {
                let now = s.ticks;
                s.next_alarm = s.queue.next_expiration(now);
            }
        });
    }
}

#[allow(unsafe_code)] // The macro defines the `#[no_mangle]` hooks embassy-time links against.
mod hooks {
    embassy_time_driver::time_driver_impl!(static DRIVER: super::TickDriver = super::TickDriver);
}
