//! A periodic SysTick time driver for embassy-time: one interrupt per millisecond (embassy's
//! tick), `now` counts them. The HIL image runs in wall-clock time (no `-icount`), where the
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
}

static STATE: Mutex<RefCell<State>> = Mutex::new(RefCell::new(State {
    ticks: 0,
    next_alarm: u64::MAX,
    queue: ConstGenericQueue::new(),
}));

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
