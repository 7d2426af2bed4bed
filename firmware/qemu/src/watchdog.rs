//! The mps2-an386's CMSDK APB watchdog (ARM DDI 0479, §4.4), at `0x4000_8000`, clocked at
//! 25 MHz: the QEMU board's stand-in for the Nucleo's IWDG.
//!
//! Started, it counts `load` cycles down; at zero it raises its interrupt (wired to the NMI)
//! and reloads; reaching zero again with the interrupt still raised, it resets the machine.
//! Feeding it ([`feed`]) clears the interrupt and reloads the counter. So a program that stops
//! feeding is reset between one and two timeouts later.

use core::ptr;

const BASE: usize = 0x4000_8000;
const LOAD: usize = BASE;
const CONTROL: usize = BASE + 0x008;
const INTCLR: usize = BASE + 0x00c;
const LOCK: usize = BASE + 0xc00;
/// `WDOGLOCK`: this value opens the other registers to writes, any other closes them.
const UNLOCK: u32 = 0x1acc_e551;
/// `WDOGCONTROL`: `INTEN` (counter and interrupt on) and `RESEN` (reset on the second zero).
const INTEN_RESEN: u32 = 0b11;
/// The watchdog's clock: the board's 25 MHz system clock.
pub const HZ: u32 = 25_000_000;

/// Writes `value` to the watchdog register at `addr`, between an unlock and a lock.
#[allow(unsafe_code)]
fn write(addr: usize, value: u32) {
    // SAFETY: `LOCK`, `LOAD`, `CONTROL` and `INTCLR` are registers of the watchdog peripheral
    // on this board (fixed addresses, always mapped, 32-bit aligned); writing them has no
    // effect on memory the program uses. Single core, and only this module touches them.
    unsafe {
        ptr::write_volatile(LOCK as *mut u32, UNLOCK);
        ptr::write_volatile(addr as *mut u32, value);
        ptr::write_volatile(LOCK as *mut u32, 0);
    }
}

/// Starts the watchdog with a timeout of `cycles` (at [`HZ`]).
pub fn start(cycles: u32) {
    write(LOAD, cycles);
    write(CONTROL, INTEN_RESEN);
}

/// Clears a raised interrupt and reloads the counter.
pub fn feed() {
    write(INTCLR, 1);
}
