//! UART0 of mps2-an386 (ARM's CMSDK APB UART), driven by interrupts, as the robot's link to the
//! host (`firmware::hil`): [`UartRx`] is an [`firmware::embedded_io_async::Read`], [`UartTx`] an
//! [`firmware::embedded_io_async::Write`].
//!
//! Receiving: the RX interrupt (IRQ 0) moves each byte from the data register into a ring of
//! [`RX_RING`] bytes and wakes the reader; bytes that find the ring full are dropped (the
//! link's decoder resynchronises at the next frame and counts the frame as bad).
//! Transmitting: a byte goes into the data register when the transmitter is free; otherwise
//! the writer waits for the TX interrupt (IRQ 1), which the UART raises when its buffer drains.
//! Under QEMU the UART is as fast as its character device (the host's pipe or socket), and
//! QEMU holds back further input while the data register is full, so nothing is lost there.

use core::cell::RefCell;
use core::convert::Infallible;
use core::future::poll_fn;
use core::task::{Poll, Waker};

use cortex_m::peripheral::NVIC;
use critical_section::Mutex;
use heapless::Deque;

/// UART0's registers.
const BASE: usize = 0x4000_4000;
const DATA: usize = BASE;
const STATE: usize = BASE + 0x04;
const CTRL: usize = BASE + 0x08;
const INTCLEAR: usize = BASE + 0x0C;
const BAUDDIV: usize = BASE + 0x10;

const STATE_TXFULL: u32 = 1 << 0;
const STATE_RXFULL: u32 = 1 << 1;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;
const CTRL_TX_INTEN: u32 = 1 << 2;
const CTRL_RX_INTEN: u32 = 1 << 3;
const INT_TX: u32 = 1 << 0;
const INT_RX: u32 = 1 << 1;

/// Bytes received and not yet read.
pub const RX_RING: usize = 512;

/// UART0's interrupts on mps2-an386 (QEMU's `mps2.c`: RX is 0, TX one more).
#[derive(Clone, Copy)]
enum Irq {
    Uart0Rx = 0,
    Uart0Tx = 1,
}

#[allow(unsafe_code)]
// SAFETY: the numbers are UART0's interrupt lines on this board, below the 240 that
// cortex-m-rt's vector table has.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

struct State {
    ring: Deque<u8, RX_RING>,
    reader: Option<Waker>,
    writer: Option<Waker>,
}

static STATE_: Mutex<RefCell<State>> = Mutex::new(RefCell::new(State {
    ring: Deque::new(),
    reader: None,
    writer: None,
}));

fn read_reg(addr: usize) -> u32 {
    #[allow(unsafe_code)]
    // SAFETY: `addr` is one of UART0's word-aligned registers, always mapped on this board.
    unsafe {
        core::ptr::read_volatile(addr as *const u32)
    }
}

fn write_reg(addr: usize, value: u32) {
    #[allow(unsafe_code)]
    // SAFETY: as in `read_reg`; writing these registers only affects UART0.
    unsafe {
        core::ptr::write_volatile(addr as *mut u32, value)
    }
}

/// Enables UART0 (both directions, both interrupts) and returns its halves. Call once.
pub fn init() -> (UartTx, UartRx) {
    // QEMU wants a divider of at least 16; the rate means nothing to it.
    write_reg(BAUDDIV, 16);
    write_reg(
        CTRL,
        CTRL_TX_EN | CTRL_RX_EN | CTRL_TX_INTEN | CTRL_RX_INTEN,
    );
    write_reg(INTCLEAR, INT_TX | INT_RX);
    #[allow(unsafe_code)]
    // SAFETY: unmasking cannot break a critical section: every handler here takes its own.
    unsafe {
        NVIC::unmask(Irq::Uart0Rx);
        NVIC::unmask(Irq::Uart0Tx);
    }
    (UartTx, UartRx)
}

/// Every device interrupt of the board lands here (cortex-m-rt's default table); UART0's are
/// handled, any other is ignored.
pub fn on_interrupt(irqn: i16) {
    critical_section::with(|cs| {
        let mut s = STATE_.borrow_ref_mut(cs);
        if irqn == Irq::Uart0Rx as i16 {
            write_reg(INTCLEAR, INT_RX);
            while read_reg(STATE) & STATE_RXFULL != 0 {
                let b = (read_reg(DATA) & 0xFF) as u8;
                // A full ring drops the byte.
                let _ = s.ring.push_back(b);
            }
            if let Some(w) = s.reader.take() {
                w.wake();
            }
        } else if irqn == Irq::Uart0Tx as i16 {
            write_reg(INTCLEAR, INT_TX);
            if let Some(w) = s.writer.take() {
                w.wake();
            }
        }
    });
}

/// True while a writer waits for the transmitter (a byte of a frame is still to go).
pub fn tx_busy() -> bool {
    critical_section::with(|cs| STATE_.borrow_ref(cs).writer.is_some())
}

/// UART0's receiving half.
pub struct UartRx;

impl firmware::embedded_io_async::ErrorType for UartRx {
    type Error = Infallible;
}

impl firmware::embedded_io_async::Read for UartRx {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        poll_fn(|cx| {
            critical_section::with(|cs| {
                let mut s = STATE_.borrow_ref_mut(cs);
                let mut n = 0;
                while let Some(slot) = buf.get_mut(n) {
                    let Some(b) = s.ring.pop_front() else { break };
                    *slot = b;
                    n += 1;
                }
                if n > 0 {
                    Poll::Ready(Ok(n))
                } else {
                    s.reader = Some(cx.waker().clone());
                    Poll::Pending
                }
            })
        })
        .await
    }
}

/// UART0's transmitting half.
pub struct UartTx;

impl firmware::embedded_io_async::ErrorType for UartTx {
    type Error = Infallible;
}

impl firmware::embedded_io_async::Write for UartTx {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        let Some(&first) = buf.first() else {
            return Ok(0);
        };
        // One byte per write: the UART holds one.
        poll_fn(|cx| {
            critical_section::with(|cs| {
                if read_reg(STATE) & STATE_TXFULL == 0 {
                    write_reg(DATA, u32::from(first));
                    Poll::Ready(Ok(1))
                } else {
                    STATE_.borrow_ref_mut(cs).writer = Some(cx.waker().clone());
                    Poll::Pending
                }
            })
        })
        .await
    }

    async fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}
