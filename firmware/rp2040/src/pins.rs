//! The pin map: which RP2040 peripheral and GPIO does what, for a Raspberry Pi Pico.
//!
//! This is the only module that names GPIO numbers; [`Board::take`] splits embassy's
//! [`Peripherals`] into the groups the other modules drive. `firmware/README.md`
//! shows the same map with the wiring.
//!
//! | function | GPIO | Pico pin |
//! |---|---|---|
//! | PS/2 port 0 data / clock | 0 / 1 | 1 / 2 |
//! | PS/2 port 1 data / clock | 2 / 3 | 4 / 5 |
//! | PS/2 port 2 data / clock | 4 / 5 | 6 / 7 |
//! | PS/2 port 3 data / clock | 6 / 7 | 9 / 10 |
//! | PS/2 port 4 data / clock | 8 / 9 | 11 / 12 |
//! | PS/2 port 5 data / clock | 10 / 11 | 14 / 15 |
//! | PS/2 port 6 data / clock | 12 / 13 | 16 / 17 |
//! | PS/2 port 7 data / clock | 14 / 15 | 19 / 20 |
//! | haptic motors 0..=6 PWM | 16..=22 | 21, 22, 24, 25, 26, 27, 29 |
//! | haptic motor 7 PWM | 28 | 34 |
//! | status LED | 25 | on board |
//!
//! PS/2 ports 0..3 run on the four state machines of PIO0, ports 4..7 on PIO1. The
//! PIO program addresses the clock line as "data + 1", so each port's two GPIOs must
//! be consecutive, data first. DMA channel *n* copies port *n*'s received words into
//! its ring in RAM (`rx_ring.rs`).

use embassy_rp::peripherals::{
    DMA_CH0, DMA_CH1, DMA_CH2, DMA_CH3, DMA_CH4, DMA_CH5, DMA_CH6, DMA_CH7, FLASH, PIN_0, PIN_1,
    PIN_10, PIN_11, PIN_12, PIN_13, PIN_14, PIN_15, PIN_16, PIN_17, PIN_18, PIN_19, PIN_2, PIN_20,
    PIN_21, PIN_22, PIN_25, PIN_28, PIN_3, PIN_4, PIN_5, PIN_6, PIN_7, PIN_8, PIN_9, PIO0, PIO1,
    PWM_SLICE0, PWM_SLICE1, PWM_SLICE2, PWM_SLICE3, PWM_SLICE6, USB, WATCHDOG,
};
use embassy_rp::{Peri, Peripherals};

/// GPIO of each PS/2 port's data line, indexed by port.
pub const PS2_DATA_GPIO: [u8; 8] = [0, 2, 4, 6, 8, 10, 12, 14];
/// GPIO of each PS/2 port's clock line (always data + 1), indexed by port.
pub const PS2_CLOCK_GPIO: [u8; 8] = [1, 3, 5, 7, 9, 11, 13, 15];
/// GPIO of each haptic motor's PWM output, indexed by paddle.
pub const HAPTIC_GPIO: [u8; 8] = [16, 17, 18, 19, 20, 21, 22, 28];
/// GPIO of the status LED (the Pico's on-board LED).
pub const LED_GPIO: u8 = 25;

/// The data (first) and clock (second) pins of one PS/2 port.
pub type Ps2PinPair<D, C> = (Peri<'static, D>, Peri<'static, C>);

/// The sixteen PS/2 lines, per port (data, clock).
pub struct Ps2Pins {
    /// Port 0: GPIO 0 data, GPIO 1 clock (PIO0 SM0).
    pub port0: Ps2PinPair<PIN_0, PIN_1>,
    /// Port 1: GPIO 2 data, GPIO 3 clock (PIO0 SM1).
    pub port1: Ps2PinPair<PIN_2, PIN_3>,
    /// Port 2: GPIO 4 data, GPIO 5 clock (PIO0 SM2).
    pub port2: Ps2PinPair<PIN_4, PIN_5>,
    /// Port 3: GPIO 6 data, GPIO 7 clock (PIO0 SM3).
    pub port3: Ps2PinPair<PIN_6, PIN_7>,
    /// Port 4: GPIO 8 data, GPIO 9 clock (PIO1 SM0).
    pub port4: Ps2PinPair<PIN_8, PIN_9>,
    /// Port 5: GPIO 10 data, GPIO 11 clock (PIO1 SM1).
    pub port5: Ps2PinPair<PIN_10, PIN_11>,
    /// Port 6: GPIO 12 data, GPIO 13 clock (PIO1 SM2).
    pub port6: Ps2PinPair<PIN_12, PIN_13>,
    /// Port 7: GPIO 14 data, GPIO 15 clock (PIO1 SM3).
    pub port7: Ps2PinPair<PIN_14, PIN_15>,
}

/// The eight haptic PWM outputs and the PWM slices behind them.
///
/// Motors 0..5 use both channels of slices 0..2, motor 6 channel A of slice 3 and
/// motor 7 channel A of slice 6 (GPIO 23 and 24 are not on the Pico's header).
pub struct HapticPins {
    /// Slice 0: motors 0 (GPIO 16, A) and 1 (GPIO 17, B).
    pub slice0: (
        Peri<'static, PWM_SLICE0>,
        Peri<'static, PIN_16>,
        Peri<'static, PIN_17>,
    ),
    /// Slice 1: motors 2 (GPIO 18, A) and 3 (GPIO 19, B).
    pub slice1: (
        Peri<'static, PWM_SLICE1>,
        Peri<'static, PIN_18>,
        Peri<'static, PIN_19>,
    ),
    /// Slice 2: motors 4 (GPIO 20, A) and 5 (GPIO 21, B).
    pub slice2: (
        Peri<'static, PWM_SLICE2>,
        Peri<'static, PIN_20>,
        Peri<'static, PIN_21>,
    ),
    /// Slice 3: motor 6 (GPIO 22, A).
    pub slice3: (Peri<'static, PWM_SLICE3>, Peri<'static, PIN_22>),
    /// Slice 6: motor 7 (GPIO 28, A).
    pub slice6: (Peri<'static, PWM_SLICE6>, Peri<'static, PIN_28>),
}

/// The DMA channels of the PS/2 receive rings, channel *n* for port *n*.
pub struct Ps2Dma {
    /// Ports 0..=3 (PIO0 SM0..=3).
    pub ch0: Peri<'static, DMA_CH0>,
    pub ch1: Peri<'static, DMA_CH1>,
    pub ch2: Peri<'static, DMA_CH2>,
    pub ch3: Peri<'static, DMA_CH3>,
    /// Ports 4..=7 (PIO1 SM0..=3).
    pub ch4: Peri<'static, DMA_CH4>,
    pub ch5: Peri<'static, DMA_CH5>,
    pub ch6: Peri<'static, DMA_CH6>,
    pub ch7: Peri<'static, DMA_CH7>,
}

/// Every peripheral the firmware uses, grouped by the module that drives it.
pub struct Board {
    /// PIO block for PS/2 ports 0..3.
    pub pio0: Peri<'static, PIO0>,
    /// PIO block for PS/2 ports 4..7.
    pub pio1: Peri<'static, PIO1>,
    /// PS/2 lines.
    pub ps2: Ps2Pins,
    /// PS/2 receive rings' DMA channels.
    pub ps2_dma: Ps2Dma,
    /// Haptic motor outputs.
    pub haptics: HapticPins,
    /// Status LED.
    pub led: Peri<'static, PIN_25>,
    /// USB device controller.
    pub usb: Peri<'static, USB>,
    /// Watchdog.
    pub watchdog: Peri<'static, WATCHDOG>,
    /// The QSPI flash (its unique id; the configuration sector).
    pub flash: Peri<'static, FLASH>,
}

impl Board {
    /// Splits the chip's peripherals by the pin map above.
    pub fn take(p: Peripherals) -> Self {
        Self {
            pio0: p.PIO0,
            pio1: p.PIO1,
            ps2: Ps2Pins {
                port0: (p.PIN_0, p.PIN_1),
                port1: (p.PIN_2, p.PIN_3),
                port2: (p.PIN_4, p.PIN_5),
                port3: (p.PIN_6, p.PIN_7),
                port4: (p.PIN_8, p.PIN_9),
                port5: (p.PIN_10, p.PIN_11),
                port6: (p.PIN_12, p.PIN_13),
                port7: (p.PIN_14, p.PIN_15),
            },
            ps2_dma: Ps2Dma {
                ch0: p.DMA_CH0,
                ch1: p.DMA_CH1,
                ch2: p.DMA_CH2,
                ch3: p.DMA_CH3,
                ch4: p.DMA_CH4,
                ch5: p.DMA_CH5,
                ch6: p.DMA_CH6,
                ch7: p.DMA_CH7,
            },
            haptics: HapticPins {
                slice0: (p.PWM_SLICE0, p.PIN_16, p.PIN_17),
                slice1: (p.PWM_SLICE1, p.PIN_18, p.PIN_19),
                slice2: (p.PWM_SLICE2, p.PIN_20, p.PIN_21),
                slice3: (p.PWM_SLICE3, p.PIN_22),
                slice6: (p.PWM_SLICE6, p.PIN_28),
            },
            led: p.PIN_25,
            usb: p.USB,
            watchdog: p.WATCHDOG,
            flash: p.FLASH,
        }
    }
}

/// Logs the pin map (handy when checking a board's wiring with a probe attached).
pub fn log_map() {
    defmt::info!(
        "pins: PS/2 data GPIO {=[u8]}, clock GPIO {=[u8]}; haptic PWM GPIO {=[u8]}; LED GPIO {=u8}",
        PS2_DATA_GPIO,
        PS2_CLOCK_GPIO,
        HAPTIC_GPIO,
        LED_GPIO
    );
}
