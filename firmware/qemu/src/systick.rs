//! A tickless SysTick time driver for embassy-time.
//!
//! SysTick counts the 25 MHz CPU clock down from its reload value and interrupts when it wraps.
//! Instead of interrupting every tick, the reload is set to reach the next alarm (at most 2²⁴
//! cycles, 0.67 s, away), so an idle robot costs a handful of interrupts per second: under
//! `qemu-system-arm -icount shift=0,sleep=off` each one lets QEMU skip straight to the next.
//!
//! Time is `base` (cycles up to the start of the current SysTick period) plus what the counter
//! has counted down since. The reload register only changes together with a counter restart,
//! so after a wrap the counter always restarts with the current `period`, and one pending,
//! not yet handled wrap is accounted for by looking at the SysTick pending bit. Everything runs
//! in a critical section (single core).

use core::cell::RefCell;
use core::task::Waker;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{SCB, SYST};
use cortex_m_rt::exception;
use critical_section::Mutex;
use embassy_time_queue_utils::queue_generic::ConstGenericQueue;

/// mps2-an386 clocks its Cortex-M4 (and SysTick) at 25 MHz.
const SYSCLK_HZ: u64 = 25_000_000;
/// CPU cycles per embassy-time tick (`tick-hz-1_000` in Cargo.toml).
const CYCLES_PER_TICK: u64 = SYSCLK_HZ / embassy_time_driver::TICK_HZ;
/// SysTick's counter has 24 bits.
const MAX_PERIOD: u64 = 1 << 24;
/// Shortest period programmed, so that an alarm in the past cannot make an interrupt storm.
const MIN_PERIOD: u64 = 1_000;

const _: () = assert!(SYSCLK_HZ.is_multiple_of(embassy_time_driver::TICK_HZ));

struct State {
    syst: Option<SYST>,
    /// Cycles elapsed up to the start of the current period.
    base: u64,
    /// Length of the current period in cycles (the reload value + 1).
    period: u64,
    /// Tick of the earliest alarm in the queue (`u64::MAX`: none).
    next_alarm: u64,
    queue: ConstGenericQueue<8>,
}

impl State {
    /// Cycles since `init`.
    fn now_cycles(&self) -> u64 {
        // A wrap that happened inside this critical section leaves SysTick pending; count it
        // once, and read the counter again if it wrapped between the two looks.
        let before = SCB::is_pendst_pending();
        let mut val = SYST::get_current();
        let after = SCB::is_pendst_pending();
        if after && !before {
            val = SYST::get_current();
        }
        let wraps = u64::from(after);
        let counted = (self.period - 1).saturating_sub(u64::from(val));
        self.base + wraps * self.period + counted
    }

    /// Restarts the counter with the period that reaches the next alarm.
    fn reprogram(&mut self) {
        let now = self.now_cycles();
        let target = self.next_alarm.saturating_mul(CYCLES_PER_TICK);
        let period = target.saturating_sub(now).clamp(MIN_PERIOD, MAX_PERIOD);
        if let Some(syst) = self.syst.as_mut() {
            // Writing the counter clears it and the wrap flag: account for what was counted,
            // including a pending wrap (whose interrupt must then not count it again).
            self.base = now;
            self.period = period;
            syst.set_reload((period - 1) as u32);
            syst.clear_current();
            SCB::clear_pendst();
        }
    }

    /// Wakes what is due and finds the next alarm.
    fn expire(&mut self) {
        let now = self.now_cycles() / CYCLES_PER_TICK;
        self.next_alarm = self.queue.next_expiration(now);
    }
}

static STATE: Mutex<RefCell<State>> = Mutex::new(RefCell::new(State {
    syst: None,
    base: 0,
    period: MAX_PERIOD,
    next_alarm: u64::MAX,
    queue: ConstGenericQueue::new(),
}));

fn with_state<R>(f: impl FnOnce(&mut State) -> R) -> R {
    critical_section::with(|cs| f(&mut STATE.borrow_ref_mut(cs)))
}

/// Starts the clock at zero; call once, before anything asks for the time.
pub fn init(mut syst: SYST) {
    syst.disable_counter();
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload((MAX_PERIOD - 1) as u32);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
    with_state(|s| {
        s.syst = Some(syst);
        s.base = 0;
        s.period = MAX_PERIOD;
    });
}

#[exception]
fn SysTick() {
    with_state(|s| {
        // The counter wrapped (and restarted with the same period): a whole period went by.
        s.base += s.period;
        s.expire();
        s.reprogram();
    });
}

struct SysTickDriver;

impl embassy_time_driver::Driver for SysTickDriver {
    fn now(&self) -> u64 {
        with_state(|s| s.now_cycles() / CYCLES_PER_TICK)
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        with_state(|s| {
            if s.queue.schedule_wake(at, waker) {
                s.expire();
                s.reprogram();
            }
        });
    }
}

#[allow(unsafe_code)] // The macro defines the `#[no_mangle]` hooks embassy-time links against.
mod hooks {
    embassy_time_driver::time_driver_impl!(static DRIVER: super::SysTickDriver = super::SysTickDriver);
}
