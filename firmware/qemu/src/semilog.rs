//! Logging over semihosting (the `log` facade), stamped with the board's time: shared by the
//! board's images.

use cortex_m_semihosting::hprintln;
use firmware::Clock;
use firmware::hal::EmbassyClock;

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

/// Logs at info level and above over semihosting from now on.
pub fn init() {
    // Only fails if a logger is already set, and nothing else sets one.
    let _ = log::set_logger(&LOGGER).map(|()| log::set_max_level(log::LevelFilter::Info));
}
