//! The real board: an aMussel controller on a Nucleo-L476RG (STM32L476RG, Cortex-M4F).
//!
//! | Function                       | Peripheral        | Pin  | Nucleo header      |
//! |--------------------------------|-------------------|------|--------------------|
//! | light transmitter (IrDA SIR)   | USART1 TX, DMA1_CH4 | PA9  | D8 (CN5-1)       |
//! | light receiver, left           | USART3 RX, DMA1_CH3 | PC11 | CN7-2            |
//! | light receiver, right          | UART5 RX, DMA2_CH2  | PD2  | CN7-4            |
//! | ambient light sensor           | ADC1 IN5          | PA0  | A0                 |
//! | oxygen sensor                  | ADC1 IN6          | PA1  | A1                 |
//! | green LED (decided: left)      | GPIO out          | PA5  | D13, also LD2      |
//! | blue LED (decided: right)      | GPIO out          | PC7  | D9                 |
//!
//! The three USARTs run IrDA SIR at [`LIGHT_BAUD`]: the transmitter's pulses drive the light
//! modulator, the receivers take the demodulated pulses. Receivers are DMA ring buffers, so no
//! byte is lost between two reads. Randomness is a PCG seeded from the chip's unique ID (every
//! robot draws differently, the same robot the same way). Logs go out as defmt over RTT.
//!
//! **Swarm key.** Built with `CIMAX_SWARM_KEY` set to 32 hex digits (a 128-bit key) and the
//! `keyed` feature, e.g. `CIMAX_SWARM_KEY=00112233445566778899aabbccddeeff cargo firmware
//! --features keyed`, the robot sends and accepts
//! only authenticated frames ([`SWARM_KEY`]); unset or empty, plain frames. A malformed key
//! fails the build. The key ends up in the flash image: keep the image as secret as the key.
//!
//! **Robot id.** Built with `CIMAX_ROBOT_ID` set to a number `0..=65535`, e.g.
//! `CIMAX_ROBOT_ID=2 cargo firmware`, the robot has that id ([`ROBOT_ID`]); its tag on the wire
//! is the id modulo 16, and robots within 12 hops of each other must differ in it (number a
//! line 0, 1, 2, … in order). Unset or empty, the id is the first two bytes of the chip's
//! unique ID, which gives no such guarantee: four robots share a tag about one time in three,
//! and robots sharing a tag drop each other's messages. The boot log says which. A malformed
//! id fails the build.
//!
//! **In the loop.** Built with the `hil` feature (`cargo firmware --features hil`), the robot
//! has no light, sensor or LEDs of its own: the robot program runs over the link of
//! `docs/hil.md` on USART2 (PA2 TX, PA3 RX, [`HIL_BAUD`] Bd), which the Nucleo's ST-LINK brings
//! to the host as its virtual COM port (`/dev/ttyACM0` on Linux), and joins the emulated arena:
//! `cimax arena --hil serial:/dev/ttyACM0 --cycle 2 ...` (docs/firmware.md). Its id, seed and
//! timing come from the host's `Setup`; the watchdog and the reset on panic stay.
//!
//! `cargo firmware` builds the release image; `cargo run -p firmware --release --target
//! thumbv7em-none-eabihf --features board-nucleo-l476 --bin nucleo_l476` flashes it with
//! probe-rs and prints the logs (see `docs/firmware.md`).

#![no_std]
#![no_main]
// The `hil` build leaves the board's own light, sensors and LEDs unused.
#![cfg_attr(feature = "hil", allow(unused_imports, dead_code))]

use core::convert::Infallible;

use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_stm32::adc::{Adc, AdcChannel, AdcConfig, AnyAdcChannel, Resolution, SampleTime};
use embassy_stm32::gpio::{Level as PinLevel, Output, Speed};
use embassy_stm32::peripherals::ADC1;
use embassy_stm32::peripherals::IWDG;
use embassy_stm32::rng::{self, Rng};
use embassy_stm32::usart::{self, UartRx, UartTx};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, dma, pac, peripherals};
use firmware::hal::{EmbassyClock, ErrorType, LedColor, Leds, Sensor};
use firmware::identity::{id_from_uid, rng_seed};
use firmware::protocol::fused::Adaptive;
use firmware::protocol::params::DecisionRule;
use firmware::protocol::{Event, Instant, KeyError, Level, Params, SwarmKey};
use firmware::{Clock, Config, Hardware, Observer, Robot};
use rand_pcg::Pcg32;
// Debug builds halt on a panic for the debugger (probe-rs prints the backtrace); release builds
// log where and reset (`panic` below).
#[cfg(debug_assertions)]
use panic_probe as _;

/// Bit rate of the light link ([`firmware::LIGHT_BITRATE`]).
const LIGHT_BAUD: u32 = firmware::LIGHT_BITRATE;
/// DMA ring buffer per receiver: two full frames.
const RX_RING: usize = 64;
/// The independent watchdog's timeout. The main loop comes round at least every 2.5 s even
/// with every device hung (`firmware/tests/robot.rs`,
/// `the_main_loop_comes_round_at_least_every_few_seconds`); the IWDG runs from the LSI
/// (32 kHz ± 15 % over temperature, RM0351 §6.2.4), so 8 s leaves room for both.
const WATCHDOG_US: u32 = 8_000_000;

/// The swarm key, from the environment variable `CIMAX_SWARM_KEY` at build time (32 hex
/// digits); `None` (plain frames) if it is unset or empty. Parsed at compile time: a malformed
/// key is a build error, not a robot that hears nobody.
const SWARM_KEY: Option<SwarmKey> = match option_env!("CIMAX_SWARM_KEY") {
    None => None,
    Some(hex) if hex.is_empty() => None,
    Some(hex) => match SwarmKey::from_hex(hex) {
        Ok(key) => Some(key),
        Err(KeyError::NotHex { .. }) => {
            panic!(
                "CIMAX_SWARM_KEY must be 32 hex digits (a 128-bit key): it has another character"
            )
        }
        Err(KeyError::Length { .. }) => {
            panic!("CIMAX_SWARM_KEY must be 32 hex digits (a 128-bit key): wrong number of digits")
        }
    },
};

// Keyed framing is a cargo feature (1.9 KB of flash): a key without it is a build error, not
// a robot that sends plain frames its keyed swarm drops.
const _: () = assert!(
    SWARM_KEY.is_none() || cfg!(feature = "keyed"),
    "CIMAX_SWARM_KEY needs the `keyed` feature: cargo firmware --features keyed"
);

/// The robot's id, from the environment variable `CIMAX_ROBOT_ID` at build time (decimal,
/// `0..=65535`); `None` (the id comes from the chip's unique ID) if it is unset or empty.
/// Parsed at compile time: a malformed id is a build error.
const ROBOT_ID: Option<u16> = match option_env!("CIMAX_ROBOT_ID") {
    None => None,
    Some(text) if text.is_empty() => None,
    Some(text) => match parse_id(text) {
        Some(id) => Some(id),
        None => panic!("CIMAX_ROBOT_ID must be a decimal number from 0 to 65535"),
    },
};

/// A decimal `u16`: digits only, no sign, at most 65535.
const fn parse_id(text: &str) -> Option<u16> {
    let digits = text.as_bytes();
    let mut value: u32 = 0;
    let mut i = 0;
    while i < digits.len() {
        let d = digits[i];
        if !d.is_ascii_digit() {
            return None;
        }
        value = value * 10 + (d - b'0') as u32;
        if value > u16::MAX as u32 {
            return None;
        }
        i += 1;
    }
    Some(value as u16)
}

/// Baud rate of the HIL link on USART2 (the ST-LINK's virtual COM port), `hil` builds.
#[cfg(feature = "hil")]
const HIL_BAUD: u32 = 115_200;
/// DMA ring buffer of the HIL link's receiver: a few link frames.
#[cfg(feature = "hil")]
const HIL_RING: usize = 256;

#[cfg(feature = "hil")]
bind_interrupts!(struct HilIrqs {
    USART2 => usart::InterruptHandler<peripherals::USART2>;
    DMA1_CHANNEL6 => dma::InterruptHandler<peripherals::DMA1_CH6>;
    DMA1_CHANNEL7 => dma::InterruptHandler<peripherals::DMA1_CH7>;
});

bind_interrupts!(struct Irqs {
    USART3 => usart::InterruptHandler<peripherals::USART3>;
    UART5 => usart::InterruptHandler<peripherals::UART5>;
    DMA1_CHANNEL3 => dma::InterruptHandler<peripherals::DMA1_CH3>;
    DMA1_CHANNEL4 => dma::InterruptHandler<peripherals::DMA1_CH4>;
    DMA2_CHANNEL2 => dma::InterruptHandler<peripherals::DMA2_CH2>;
    RNG => rng::InterruptHandler<peripherals::RNG>;
});

/// Feeds the independent watchdog on every round of the robot's main loop
/// ([`Observer::progress`]): a robot that stops coming round is reset within
/// [`WATCHDOG_US`].
struct Watchdog<'d>(IndependentWatchdog<'d, IWDG>);

impl Observer for Watchdog<'_> {
    fn event(&mut self, _: Instant, _: &Event) {}

    fn progress(&mut self, _: Instant) {
        self.0.pet();
    }
}

/// What reset the chip last (RCC_CSR, RM0351 §6.4.29), for the boot log; clears the flags.
fn reset_cause() -> &'static str {
    let csr = pac::RCC.csr().read();
    let cause = if csr.iwdgrstf() {
        "the watchdog (the robot stopped making progress)"
    } else if csr.sftrstf() {
        "software (a panic, or a debugger)"
    } else if csr.borrstf() {
        "power (brown-out or power-on)"
    } else if csr.lpwrrstf() || csr.wwdgrstf() {
        "low-power or window watchdog"
    } else if csr.pinrstf() {
        "the reset pin"
    } else {
        "unknown"
    };
    pac::RCC.csr().modify(|w| w.set_rmvf(true));
    cause
}

/// Switches a configured USART to IrDA SIR (normal power): `IREN` may only change while the
/// USART is disabled, and the IrDA prescaler must be 1.
fn irda(regs: pac::usart::Usart) {
    regs.cr1().modify(|w| w.set_ue(false));
    regs.gtpr().modify(|w| w.set_psc(1));
    regs.cr3().modify(|w| w.set_iren(true));
    regs.cr1().modify(|w| w.set_ue(true));
}

/// Ambient light and oxygen on two ADC1 channels, 8-bit conversions.
struct AdcSensor<'d> {
    adc: Adc<'d, ADC1>,
    light: AnyAdcChannel<'d, ADC1>,
    oxygen: AnyAdcChannel<'d, ADC1>,
}

impl ErrorType for AdcSensor<'_> {
    type Error = Infallible;
}

impl Sensor for AdcSensor<'_> {
    async fn ambient_light(&mut self) -> Result<Level, Infallible> {
        let raw = self
            .adc
            .blocking_read(&mut self.light, SampleTime::CYCLES640_5);
        Ok(Level(raw.min(255) as u8))
    }

    async fn oxygen(&mut self) -> Result<Level, Infallible> {
        let raw = self
            .adc
            .blocking_read(&mut self.oxygen, SampleTime::CYCLES640_5);
        Ok(Level(raw.min(255) as u8))
    }
}

/// The top-cap LEDs on two GPIOs.
struct TopCap<'d> {
    green: Output<'d>,
    blue: Output<'d>,
}

impl ErrorType for TopCap<'_> {
    type Error = Infallible;
}

impl Leds for TopCap<'_> {
    async fn show(&mut self, color: LedColor) -> Result<(), Infallible> {
        self.green
            .set_level(PinLevel::from(color == LedColor::Green));
        self.blue.set_level(PinLevel::from(color == LedColor::Blue));
        Ok(())
    }
}

#[embassy_executor::main]
async fn main(_spawner: Spawner) {
    let mut config = embassy_stm32::Config::default();
    {
        use embassy_stm32::rcc::{LsConfig, Pll, PllMul, PllPreDiv, PllQDiv, PllSource, mux};
        // The ADC's kernel clock: SYSCLK (MSI 4 MHz by default).
        config.rcc.mux.adcsel = mux::Adcsel::SYS;
        // The Nucleo's 32.768 kHz crystal (LSE, X2). With it, embassy-stm32 puts the MSI in
        // PLL mode (MSIPLLEN): the MSI, and with it SYSCLK, the timers and embassy-time, is
        // locked to the crystal instead of drifting by up to ±1.5 % (docs/firmware.md,
        // "Timing"). The LSI stays on for the watchdog.
        config.rcc.ls = LsConfig {
            lsi: true,
            ..LsConfig::default_lse()
        };
        // 48 MHz for the RNG only (the L476 has no HSI48): PLLSAI1 from the MSI,
        // 4 MHz × 24 / 2. Switched off again once the seed is drawn.
        config.rcc.pllsai1 = Some(Pll {
            source: PllSource::MSI,
            prediv: PllPreDiv::DIV1,
            mul: PllMul::MUL24,
            divp: None,
            divq: Some(PllQDiv::DIV2),
            divr: None,
        });
        config.rcc.mux.clk48sel = mux::Clk48sel::PLLSAI1_Q;
    }
    let p = embassy_stm32::init(config);
    defmt::info!(
        "aMussel on Nucleo-L476RG, uid {}, reset by {=str}",
        embassy_stm32::uid::uid_hex(),
        reset_cause()
    );
    // Started first, so a hang anywhere below (a clock that never settles, a driver that
    // spins) resets the robot too.
    let mut watchdog = IndependentWatchdog::new(p.IWDG, WATCHDOG_US);
    watchdog.unleash();

    // 16 bytes from the hardware RNG, then its 48 MHz clock goes off.
    let mut draw = [0u8; 16];
    let hardware = {
        let mut trng = Rng::new(p.RNG, Irqs);
        trng.async_fill_bytes(&mut draw).await.is_ok()
    };
    pac::RCC.cr().modify(|w| w.set_pllsai1on(false));
    if !hardware {
        defmt::warn!("hardware RNG failed: seeding from the unique ID alone");
    }

    #[cfg(feature = "hil")]
    {
        // The robot in the loop: the robot program over the HIL link on USART2.
        use firmware::hil::robot::{Link, RNG_STREAM, run};
        let mut link_config = usart::Config::default();
        link_config.baudrate = HIL_BAUD;
        let uart = match usart::Uart::new(
            p.USART2,
            p.PA3,
            p.PA2,
            p.DMA1_CH7,
            p.DMA1_CH6,
            HilIrqs,
            link_config,
        ) {
            Ok(u) => u,
            Err(e) => defmt::panic!("HIL link: {}", e),
        };
        let (tx, rx) = uart.split();
        let mut ring = [0u8; HIL_RING];
        let rx = rx.into_ring_buffered(&mut ring);
        let link = Link::<_, 2>::new(tx);
        let uid = embassy_stm32::uid::uid();
        let base = Config {
            id: ROBOT_ID.unwrap_or_else(|| id_from_uid(&uid)),
            ..Config::robots()
        };
        defmt::info!("in the loop: the HIL link on USART2 at {} Bd", HIL_BAUD);
        let mut dog = Watchdog(watchdog);
        let rng = |seed: u32| Pcg32::new(u64::from(seed), RNG_STREAM);
        match run(&link, rx, &EmbassyClock, base, rng, &mut dog).await {}
    }

    // The robot with its own light, sensors and LEDs.
    #[cfg(not(feature = "hil"))]
    {
        let mut link = usart::Config::default();
        link.baudrate = LIGHT_BAUD;

        let tx = match UartTx::new(p.USART1, p.PA9, p.DMA1_CH4, Irqs, link) {
            Ok(tx) => tx,
            Err(e) => defmt::panic!("transmitter: {}", e),
        };
        irda(pac::USART1);
        let left = match UartRx::new(p.USART3, p.PC11, p.DMA1_CH3, Irqs, link) {
            Ok(rx) => rx,
            Err(e) => defmt::panic!("left receiver: {}", e),
        };
        irda(pac::USART3);
        let right = match UartRx::new(p.UART5, p.PD2, p.DMA2_CH2, Irqs, link) {
            Ok(rx) => rx,
            Err(e) => defmt::panic!("right receiver: {}", e),
        };
        irda(pac::UART5);
        let mut left_ring = [0u8; RX_RING];
        let mut right_ring = [0u8; RX_RING];

        let adc_config = AdcConfig {
            resolution: Some(Resolution::BITS8),
            ..AdcConfig::default()
        };
        let sensor = AdcSensor {
            adc: Adc::new_with_config(p.ADC1, adc_config),
            light: p.PA0.degrade_adc(),
            oxygen: p.PA1.degrade_adc(),
        };
        let leds = TopCap {
            green: Output::new(p.PA5, PinLevel::Low, Speed::Low),
            blue: Output::new(p.PC7, PinLevel::Low, Speed::Low),
        };

        let mut hw = Hardware::line(
            tx,
            left.into_ring_buffered(&mut left_ring),
            right.into_ring_buffered(&mut right_ring),
            sensor,
            leds,
            EmbassyClock,
        );

        let uid = embassy_stm32::uid::uid();
        let (state, stream) = rng_seed(&uid, hardware.then_some(draw));
        let rng = Pcg32::new(state, stream);
        let id = match ROBOT_ID {
            Some(id) => id,
            None => {
                defmt::warn!(
                    "CIMAX_ROBOT_ID not set at build time: id hashed from the chip's unique ID, its \
                     tag may collide with a neighbour's"
                );
                id_from_uid(&uid)
            }
        };
        // The adaptive decision rule: the LEDs show the swarm's direction after about two cycles
        // instead of ten, with every bar of the emulated campaign met (docs/protocol.md §5.4,
        // docs/reliability.md); `cimax arena` keeps the paper's fixed period by default.
        let config = Config {
            id,
            key: SWARM_KEY,
            params: Params {
                decide: DecisionRule::Adaptive,
                ..Params::robots()
            },
            ..Config::robots()
        };
        let mut robot = match Robot::<_, 2, Adaptive>::new(config, hw.clock.now(), rng) {
            Ok(robot) => robot,
            Err(e) => defmt::panic!("setup: {}", e),
        };
        match robot.run_observed(&mut hw, &mut Watchdog(watchdog)).await {}
    }
}

/// Release builds: a deployed robot must come back by itself, so a panic resets the chip; the
/// robot boots, re-reads its sensors and negotiates again, and its boot log names the cause
/// (`reset_cause`). The handler logs nothing: logging the panic's place keeps every panic
/// site's file and line in the image, 6.4 KB measured (docs/firmware.md, "Footprint"); debug
/// builds halt with panic-probe's full message instead.
#[cfg(not(debug_assertions))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}
