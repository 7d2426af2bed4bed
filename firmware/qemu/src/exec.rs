//! A tiny executor: polls one future when it was woken, sleeps in WFI otherwise (which lets
//! QEMU's `-icount sleep=off` jump straight to the next interrupt). Shared by the board's two
//! images (the four-robot check and the robot in the loop).

use core::future::Future;
use core::pin::pin;
use core::sync::atomic::{AtomicBool, Ordering};
use core::task::{Context, Poll, RawWaker, RawWakerVTable, Waker};

static WOKEN: AtomicBool = AtomicBool::new(true);

fn wake(_: *const ()) {
    WOKEN.store(true, Ordering::Release);
}

fn clone(data: *const ()) -> RawWaker {
    RawWaker::new(data, &VTABLE)
}

fn drop(_: *const ()) {}

static VTABLE: RawWakerVTable = RawWakerVTable::new(clone, wake, wake, drop);

/// Runs `future` to completion on this core.
#[allow(dead_code)] // the four-robot image's; the HIL images use `block_on_idle`
pub fn block_on<F: Future>(future: F) -> F::Output {
    block_on_idle(future, || {})
}

/// Runs `future` to completion on this core, calling `idle` whenever it is not woken, before
/// sleeping (`idle` may wake it: then it is polled again at once).
pub fn block_on_idle<F: Future>(future: F, mut idle: impl FnMut()) -> F::Output {
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
            idle();
            if WOKEN.load(Ordering::Acquire) {
                continue;
            }
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
