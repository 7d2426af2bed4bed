//! What the QEMU board remembers across a reset: a few words in `.uninit` RAM, which
//! cortex-m-rt neither loads nor zeroes and a QEMU system reset leaves alone (QEMU reloads
//! the image's loadable sections, not RAM). A magic word tells a record from power-on garbage.

use core::mem::MaybeUninit;
use core::ptr;

/// How far the recovery check got before the last reset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Power-on: no record.
    Cold,
    /// The image is about to panic on purpose; the panic handler should reset it.
    PanicExpected,
    /// The panic handler reset the board after the expected panic.
    AfterPanic,
    /// A robot's main loop is about to hang; the watchdog should reset the board.
    HangExpected,
    /// Anything else: an unexpected panic or reset.
    Unexpected,
}

const MAGIC: u32 = 0xc1a4_0b07;

#[repr(C)]
#[derive(Clone, Copy)]
struct Record {
    magic: u32,
    stage: u32,
    /// 1 if every check before the reset passed.
    ok: u32,
}

#[allow(unsafe_code)]
#[unsafe(link_section = ".uninit.BOOT")]
static mut RECORD: MaybeUninit<Record> = MaybeUninit::uninit();

impl Stage {
    fn code(self) -> u32 {
        match self {
            Stage::Cold => 0,
            Stage::PanicExpected => 1,
            Stage::AfterPanic => 2,
            Stage::HangExpected => 3,
            Stage::Unexpected => 4,
        }
    }

    fn of(code: u32) -> Stage {
        match code {
            0 => Stage::Cold,
            1 => Stage::PanicExpected,
            2 => Stage::AfterPanic,
            3 => Stage::HangExpected,
            _ => Stage::Unexpected,
        }
    }
}

/// The stage recorded before the last reset and whether every check so far passed;
/// `(Cold, true)` without a record.
#[allow(unsafe_code)]
pub fn load() -> (Stage, bool) {
    // SAFETY: `RECORD` is plain words in RAM owned by this module; a volatile read of
    // possibly uninitialised memory of a type without invalid bit patterns (three `u32`s)
    // gives some value, which the magic word then accepts or not. Single core, no interrupt
    // handler touches it.
    let r = unsafe { ptr::read_volatile((&raw const RECORD).cast::<Record>()) };
    if r.magic == MAGIC {
        (Stage::of(r.stage), r.ok == 1)
    } else {
        (Stage::Cold, true)
    }
}

/// Records `stage` and `ok` for the next boot.
#[allow(unsafe_code)]
pub fn store(stage: Stage, ok: bool) {
    let r = Record {
        magic: MAGIC,
        stage: stage.code(),
        ok: u32::from(ok),
    };
    // SAFETY: as in `load`; the write initialises the record. The panic handler may call this
    // while `main` was between two calls, which is fine: each call writes the whole record.
    unsafe { ptr::write_volatile((&raw mut RECORD).cast::<Record>(), r) }
}

/// Forgets the record: the next boot is a cold one.
#[allow(unsafe_code)]
pub fn clear() {
    // SAFETY: as in `store`.
    unsafe { ptr::write_volatile((&raw mut RECORD).cast::<u32>(), 0) }
}
