//! Space Foosball sensor board firmware for the RP2040 (Raspberry Pi Pico).
//!
//! Eight optical PS/2 mice watch the eight rods; the PIO state machines run their
//! wire protocol ([`ps2_pio`]), the platform-free `sensor-board` crate drives and
//! decodes them ([`sensor_loop`]), and a USB HID interface sends the paddle motion
//! every millisecond and takes haptic pulses and the LED state back ([`usb_hid`],
//! [`haptics`], [`led`]). A watchdog resets the chip if the sensor loop or the IN reports stall
//! ([`watchdog`]); two resets in quick succession enter the USB bootloader
//! ([`double_tap`]); [`pins`] is the pin map.
//!
//! This file only wires the parts together.
#![no_std]
#![no_main]

mod board_flash;
mod config_store;
mod double_tap;
mod feature;
mod haptics;
mod led;
mod panic;
mod pins;
mod ps2_pio;
mod rx_ring;
mod sensor_loop;
mod usb_hid;
mod usb_in_flight;
mod version;
mod watchdog;

use defmt::unwrap;
use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_rp::bind_interrupts;
use embassy_rp::peripherals::{PIO0, PIO1, USB};
use embassy_rp::pio::{self, Pio};
use embassy_rp::usb;

bind_interrupts!(struct Irqs {
    USBCTRL_IRQ => usb_in_flight::TakenHandler, usb::InterruptHandler<USB>;
    PIO0_IRQ_0 => pio::InterruptHandler<PIO0>;
    PIO1_IRQ_0 => pio::InterruptHandler<PIO1>;
});

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let board = pins::Board::take(embassy_rp::init(Default::default()));
    defmt::info!("Space Foosball sensor board starting");
    if double_tap::second_reset() {
        defmt::warn!(
            "reset twice within {} ms: restarting into the USB bootloader",
            double_tap::WINDOW.as_millis()
        );
        embassy_rp::rom_data::reset_to_usb_boot(0, 0);
    }
    let panicked = panic::take_last();
    if let Some(message) = &panicked {
        defmt::warn!("the previous run panicked: {=str}", message.as_str());
    }
    pins::log_map();

    let (watchdog, reset_reason) = watchdog::Watchdog::start(board.watchdog, panicked.is_some());
    let ports = ps2_pio::Ps2Ports::new(
        Pio::new(board.pio0, Irqs),
        Pio::new(board.pio1, Irqs),
        board.ps2,
        board.ps2_dma,
    );
    let haptics = haptics::Haptics::new(board.haptics);
    let mut flash = board_flash::open(board.flash);
    let serial = board_flash::serial_number(&mut flash);
    let (store, kept) = config_store::load(flash);
    if let Some(settings) = kept {
        sensor_loop::with_board(|sensors| sensors.apply_settings(&settings));
    }
    let usb = usb_hid::Usb::new(usb::Driver::new(board.usb, Irqs), serial, reset_reason);

    spawner.spawn(unwrap!(sensor_loop::sensor_task(ports, watchdog)));
    spawner.spawn(unwrap!(haptics::haptics_task(haptics)));
    spawner.spawn(unwrap!(led::led_task(board.led)));
    spawner.spawn(unwrap!(usb_hid::usb_device_task(usb.device)));
    spawner.spawn(unwrap!(usb_hid::report_in_task(usb.writer)));
    spawner.spawn(unwrap!(usb_hid::report_out_task(usb.reader)));
    spawner.spawn(unwrap!(feature::bootloader_task()));
    spawner.spawn(unwrap!(config_store::save_task(store, kept)));
    spawner.spawn(unwrap!(double_tap::wipe_task()));
}
