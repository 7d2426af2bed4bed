//! The robot in the loop in this process: the unchanged `firmware::hil::robot::run` over a
//! channel, on the run's virtual clock. It tests the link and the bridge without QEMU,
//! deterministically.

use embedded_io_async::{ErrorKind, ErrorType, Write};
use firmware::Config;
use firmware::hil::robot::Link;
use rand_pcg::Pcg32;
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender};

use crate::board::clock::EmuClock;
use crate::board::light::EmuReceiver;

/// The robot program in this process, over the link (`firmware::hil::robot::run`), with as
/// many receivers as `base` has sectors.
pub(super) async fn in_process(
    to_host: UnboundedSender<Vec<u8>>,
    from_host: UnboundedReceiver<Vec<u8>>,
    clock: EmuClock,
    base: Config,
) {
    async fn with<const N: usize>(
        to_host: UnboundedSender<Vec<u8>>,
        from_host: UnboundedReceiver<Vec<u8>>,
        clock: EmuClock,
        base: Config,
    ) {
        let link = Link::<_, N>::new(ChanWriter(to_host));
        // A channel of byte chunks read as a stream: what a light receiver is.
        let reader = EmuReceiver::new(from_host);
        let _ = firmware::hil::robot::run(
            &link,
            reader,
            &clock,
            base,
            |seed| Pcg32::new(u64::from(seed), firmware::hil::robot::RNG_STREAM),
            &mut (),
        )
        .await;
    }
    match base.params.sectors {
        2 => with::<2>(to_host, from_host, clock, base).await,
        3 => with::<3>(to_host, from_host, clock, base).await,
        4 => with::<4>(to_host, from_host, clock, base).await,
        5 => with::<5>(to_host, from_host, clock, base).await,
        6 => with::<6>(to_host, from_host, clock, base).await,
        7 => with::<7>(to_host, from_host, clock, base).await,
        _ => with::<8>(to_host, from_host, clock, base).await,
    }
}

/// A channel's sending end as an [`embedded_io_async::Write`].
pub(super) struct ChanWriter(pub(super) UnboundedSender<Vec<u8>>);

impl ErrorType for ChanWriter {
    type Error = ErrorKind;
}

impl Write for ChanWriter {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        self.0
            .send(buf.to_vec())
            .map_err(|_| ErrorKind::BrokenPipe)?;
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}
