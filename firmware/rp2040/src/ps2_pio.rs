//! PS/2 host ports on the PIO state machines: the wire timing of both directions.
//!
//! One program ([`Ps2Program`]) is loaded per PIO block; each of the eight state
//! machines runs it for one port. It
//!
//! * receives device-to-host frames: on each falling clock edge it samples the data
//!   line, and after 11 bits (start, 8 data, parity, stop) autopush hands the raw
//!   bits to the RX FIFO. Parity and framing are checked in software
//!   (`Ps2Frame::decode` in `sensor-board`). If the clock stays high for more than
//!   ~130 µs inside a frame the partial frame is dropped, so the program always
//!   re-synchronises on the next start bit.
//! * sends host-to-device commands: a word in the TX FIFO starts request-to-send
//!   (clock low ≈ 135 µs, data low, clock released), then the program puts one bit
//!   on the data line at each falling clock edge the device generates (8 data LSB
//!   first, odd parity, stop), and samples the ACK on the 11th clock. A completion
//!   word in the RX FIFO reports it.
//!
//! Both lines are open-drain, emulated with pin directions: the output latches stay
//! 0, a line is pulled low by making it an output and released by making it an input
//! (pulled up: internal pull-up here, the 5 V pull-ups behind the level shifter).
//!
//! Each state machine's RX FIFO is drained by DMA into a ring in RAM ([`RxRing`]), so
//! no word is lost while the CPU is away (a flash erase).
//!
//! The software side ([`PioPs2Port`]) turns the received words into [`Ps2Event`]s and
//! enforces the send timeout: the program waits on the device's clock without a
//! time limit, so when no completion arrives in [`SEND_TIMEOUT_US`] the port reports
//! the failure and restarts its state machine.

use embassy_rp::pac;
use embassy_rp::peripherals::{PIO0, PIO1};
use embassy_rp::pio::program::{pio_asm, InstructionOperands, SetDestination};
use embassy_rp::pio::{
    Common, Config, Direction, Instance, LoadedProgram, Pin, Pio, PioPin, ShiftConfig,
    ShiftDirection, StateMachine,
};
use embassy_rp::pio_programs::clock_divider::calculate_pio_clock_divider;
use embassy_rp::{gpio, Peri};
use sensor_board::{HostFrame, LineFault, Ps2Frame, SendError, PORTS};

use crate::pins::{Ps2Dma, Ps2Pins};
use crate::rx_ring::RxRing;

/// PIO clock: one instruction cycle per microsecond, the time unit of the delays in
/// the program.
const PIO_CLOCK_HZ: u32 = 1_000_000;

/// How long after queueing a command its completion must arrive: the device starts
/// clocking within 15 ms of request-to-send and finishes the frame within 2 ms
/// (PS/2 spec), plus margin.
pub const SEND_TIMEOUT_US: u64 = 25_000;

/// Bits of a device-to-host frame.
const FRAME_BITS: u32 = 11;
/// Bits the device clocks in for a command (8 data, parity, stop).
const HOST_FRAME_BITS: u8 = 10;
/// The command bits of a TX FIFO word.
const HOST_FRAME_MASK: u16 = (1 << HOST_FRAME_BITS) - 1;

/// Set in every completion word (bits 0..=30 are all ones); never set in a received
/// frame, whose bits sit at the top of the word (autopush of 11 bits shifted right).
const COMPLETION_MARK: u32 = 1;
/// Bit of a completion word holding the data line at the ACK clock: 0 = acknowledged.
const ACK_NOT_PULLED: u32 = 1 << 31;
/// Set in every command word so the program's "TX FIFO empty" test (`pull noblock`
/// copies X = 0 when empty) sees a non-zero word even for an all-zero bit pattern.
const COMMAND_MARK: u32 = 1 << 31;

/// The PS/2 host program, loaded once into a PIO block and shared by its four state
/// machines.
pub struct Ps2Program<'d, PIO: Instance> {
    program: LoadedProgram<'d, PIO>,
    /// Offset of the idle loop's entry (`set x, 0`).
    idle: u8,
    /// Offset of the first instruction after the device's first clock of a command:
    /// a state machine stuck at or after it has started a transfer.
    tx_bits: u8,
}

impl<'d, PIO: Instance> Ps2Program<'d, PIO> {
    /// Assembles the program and loads it into the block's instruction memory.
    pub fn new(common: &mut Common<'d, PIO>) -> Self {
        let assembled = pio_asm!(
            r#"
            ; Pins: IN base = data, so `pin 0` is data and `pin 1` the clock; JMP pin =
            ; clock; SET base = data, 2 pins (bit 0 data, bit 1 clock) written as pin
            ; directions (1 = pull low); OUT base = data, 1 pin, also as direction.
            ; ISR shifts right with autopush at 11 bits; OSR shifts right, pull
            ; threshold 10 (so `!osre` counts the 10 command bits), no autopull.
            ; One cycle = 1 us.

            ; Every falling clock edge, the start bit's too, counts only if the clock
            ; is still low 10 us after it was seen low: shorter low pulses (glitches;
            ; PS/2's low phase is at least 30 us) are ignored. Data is sampled then,
            ; 10-21 us into the low phase.
            receive:
                set y, 10                 ; 11 bits: start, 8 data, parity, stop
            rx_next:
                set x, 11                 ; the clock may stay high 12 x 11 us
            rx_wait:
                jmp pin, rx_high [9]      ; clock high: keep waiting
                jmp pin, rx_high          ; low 10 us ago, high now: a glitch
                in pins, 1                ; a real low phase: sample data
                wait 1 pin 1              ; clock released
                jmp y--, rx_next
                jmp idle                  ; frame complete (autopush has sent it)
            rx_high:
                jmp x--, rx_wait
                mov isr, null             ; timed out: drop the partial frame

            .wrap_target
            public idle:
                set x, 0                  ; `pull noblock` copies X if the FIFO is empty
            idle_loop:
                jmp pin, check_tx         ; clock high: the line is idle
                jmp receive               ; clock low: the device sends a start bit
            check_tx:
                pull noblock
                mov x, osr
                jmp !x, idle_loop         ; nothing to send

            ; Request-to-send. OSR: the 10 command bits inverted (1 = pull low).
                set pindirs, 2            ; inhibit: clock low, data released
                set x, 31
            hold:
                jmp x--, hold [3]         ; hold the clock low 32 x 4 us
                set pindirs, 3 [4]        ; data low too: the start bit
                set pindirs, 1            ; release the clock
                wait 1 pin 1              ; clock back high
                wait 0 pin 1              ; the device starts clocking
            public tx_bits:
                out pindirs, 1            ; the next bit, while the clock is low
                wait 1 pin 1              ; the device samples on the rising edge
                wait 0 pin 1
                jmp !osre, tx_bits
                mov isr, ~null            ; 11th clock low: the ACK
                in pins, 1                ; bit 31 = data line, 0 = acknowledged
                push noblock
                wait 1 pin 1              ; end of the ACK clock
            .wrap
            "#
        );
        let program = common.load_program(&assembled.program);
        Self {
            program,
            idle: assembled.public_defines.idle as u8,
            tx_bits: assembled.public_defines.tx_bits as u8,
        }
    }
}

/// What a port reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum Ps2Event {
    /// A device-to-host frame arrived (11 raw bits, not yet checked).
    Frame(Ps2Frame),
    /// The command queued with [`Ps2Port::send`] is done.
    Sent(Result<(), SendError>),
    /// The RX FIFO was full when a frame completed (`FDEBUG.RXSTALL`): the program
    /// stalled on its push and missed clock edges, so the state machine was
    /// restarted; the frames still queued were dropped with it.
    RxStall,
}

/// A PS/2 host port, independent of which PIO block and state machine runs it.
pub trait Ps2Port {
    /// The next event, if any. Call often (the RX FIFO holds four words, about 2.5 ms
    /// of back-to-back frames); `now_us` drives the send timeout.
    fn next_event(&mut self, now_us: u64) -> Option<Ps2Event>;

    /// A line held low now although this side drives neither (call while no
    /// command is in flight, so the state machine has both lines released).
    fn line_fault(&self) -> Option<LineFault>;

    /// Whether a command is in flight (request-to-send, the host driving a line).
    fn sending(&self) -> bool;

    /// Sends a command; its outcome arrives as [`Ps2Event::Sent`]. A command still in
    /// flight is abandoned (its outcome never reported): the caller only sends anew
    /// once it has given up on the previous one.
    fn send(&mut self, frame: HostFrame, now_us: u64);
}

/// One PS/2 port on state machine `SM` of PIO block `PIO`: the state machine and
/// the port's state ([`PortCore`], where the logic is, so that it exists once in
/// flash rather than once per state machine).
pub struct PioPs2Port<'d, PIO: Instance, const SM: usize> {
    wire: Wire<'d, PIO, SM>,
    core: PortCore,
}

/// A port's state machine and the ring its RX FIFO drains into.
struct Wire<'d, PIO: Instance, const SM: usize> {
    sm: StateMachine<'d, PIO, SM>,
    rx: RxRing,
    /// The ring overflowed (words lost): reported as an RX stall.
    overflowed: bool,
}

/// The state machine configuration of a port with lines `data` and `clock`
/// (one copy per PIO block, not per state machine).
#[inline(never)]
fn port_config<'d, PIO: Instance>(
    program: &Ps2Program<'d, PIO>,
    data: &Pin<'d, PIO>,
    clock: &Pin<'d, PIO>,
) -> Config<'d, PIO> {
    let mut cfg = Config::default();
    cfg.use_program(&program.program, &[]);
    cfg.set_in_pins(&[data, clock]);
    cfg.set_jmp_pin(clock);
    cfg.set_set_pins(&[data, clock]);
    cfg.set_out_pins(&[data]);
    cfg.shift_in = ShiftConfig {
        threshold: FRAME_BITS as u8,
        direction: ShiftDirection::Right,
        auto_fill: true,
    };
    cfg.shift_out = ShiftConfig {
        threshold: HOST_FRAME_BITS,
        direction: ShiftDirection::Right,
        auto_fill: false,
    };
    cfg.clock_divider = calculate_pio_clock_divider(PIO_CLOCK_HZ);
    cfg
}

/// What [`PortCore`] needs of a state machine.
trait Machine {
    /// `FDEBUG.RXSTALL` for this state machine.
    fn rx_stalled(&mut self) -> bool;
    /// Words in the RX FIFO.
    fn rx_level(&mut self) -> u8;
    /// The next RX FIFO word, if any.
    fn rx_pull(&mut self) -> Option<u32>;
    /// Pushes a word into the TX FIFO.
    fn tx_push(&mut self, word: u32);
    /// The program counter.
    fn addr(&self) -> u8;
    /// Stops, drops FIFO contents, releases both lines, restarts at `idle_addr`.
    fn restart_at(&mut self, idle_addr: u8);
}

impl<PIO: Instance, const SM: usize> Machine for Wire<'_, PIO, SM> {
    fn rx_stalled(&mut self) -> bool {
        self.overflowed || self.sm.rx().stalled()
    }

    fn rx_level(&mut self) -> u8 {
        self.rx.level().min(usize::from(u8::MAX)) as u8
    }

    fn rx_pull(&mut self) -> Option<u32> {
        match self.rx.pull() {
            Ok(word) => word,
            Err(_lost) => {
                self.overflowed = true;
                self.rx.clear();
                None
            }
        }
    }

    fn tx_push(&mut self, word: u32) {
        self.sm.tx().push(word);
    }

    fn addr(&self) -> u8 {
        self.sm.get_addr()
    }

    fn restart_at(&mut self, idle_addr: u8) {
        const RELEASE_BOTH: u16 = InstructionOperands::SET {
            destination: SetDestination::PINDIRS,
            data: 0,
        }
        .encode();
        let sm = &mut self.sm;
        sm.set_enable(false);
        sm.restart();
        sm.clear_fifos();
        self.rx.clear();
        self.overflowed = false;
        // SAFETY: the state machine is stopped; SET PINDIRS touches only this port's
        // two lines (SET base/count from the config) and JMP only moves its PC.
        unsafe {
            sm.exec_instr(RELEASE_BOTH);
            sm.exec_jmp(idle_addr);
        }
        sm.set_enable(true);
    }
}

/// One port's state, apart from its state machine.
struct PortCore {
    /// Where the program was loaded.
    origin: u8,
    /// Absolute address of the idle loop's entry.
    idle_addr: u8,
    /// Offset of the bit-transfer part of a command in the program.
    transfer_offset: u8,
    /// GPIO of the data line; the clock is the next one.
    data_pin: u8,
    /// When the command in flight times out.
    send_deadline: Option<u64>,
    /// A restart after an RX stall abandoned the command in flight: its failure is
    /// reported next.
    abandoned: bool,
    /// After an RX stall: how many words the FIFO held when it was seen (complete
    /// frames from before the stall), still to deliver before the restart.
    stalled_words: Option<u8>,
}

impl<'d, PIO: Instance, const SM: usize> PioPs2Port<'d, PIO, SM> {
    /// Configures state machine `sm` for the port with data line `data` and clock
    /// line `clock` (the GPIO right after `data`) and starts it.
    pub fn new(
        common: &mut Common<'d, PIO>,
        mut sm: StateMachine<'d, PIO, SM>,
        rx: RxRing,
        program: &Ps2Program<'d, PIO>,
        data: Peri<'d, impl PioPin>,
        clock: Peri<'d, impl PioPin>,
    ) -> Self {
        let mut data = common.make_pio_pin(data);
        let mut clock = common.make_pio_pin(clock);
        assert!(
            clock.pin() == data.pin() + 1,
            "PS/2 clock must be the GPIO after data"
        );
        data.set_pull(gpio::Pull::Up);
        clock.set_pull(gpio::Pull::Up);
        // Output latches 0 for good: the program only changes pin directions.
        sm.set_pins(gpio::Level::Low, &[&data, &clock]);
        sm.set_pin_dirs(Direction::In, &[&data, &clock]);

        sm.set_config(&port_config(program, &data, &clock));

        let origin = program.program.origin;
        let idle_addr = (origin + program.idle) % 32;
        let mut wire = Wire {
            sm,
            rx,
            overflowed: false,
        };
        wire.restart_at(idle_addr);
        Self {
            wire,
            core: PortCore {
                origin,
                idle_addr,
                transfer_offset: program.tx_bits,
                data_pin: data.pin(),
                send_deadline: None,
                abandoned: false,
                stalled_words: None,
            },
        }
    }
}

impl PortCore {
    /// Restarts the state machine in the idle loop.
    fn restart(&self, sm: &mut dyn Machine) {
        sm.restart_at(self.idle_addr);
    }

    /// The next frame or command completion from the RX FIFO, if any.
    fn pull_event(&mut self, sm: &mut dyn Machine) -> Option<Ps2Event> {
        while let Some(word) = sm.rx_pull() {
            if word & COMPLETION_MARK == 0 {
                let raw = (word >> (32 - FRAME_BITS)) as u16;
                return Some(Ps2Event::Frame(Ps2Frame::from_raw(raw)));
            }
            // A completion with nothing in flight cannot happen (a timeout clears the
            // FIFOs); skip it rather than report a send nobody asked for.
            if self.send_deadline.take().is_some() {
                let result = if word & ACK_NOT_PULLED == 0 {
                    Ok(())
                } else {
                    Err(SendError::NoAck)
                };
                return Some(Ps2Event::Sent(result));
            }
        }
        None
    }

    /// Why the command in flight failed, judged from where the program waits.
    fn stuck_reason(&self, sm: &dyn Machine) -> SendError {
        let offset = sm.addr().wrapping_sub(self.origin) % 32;
        // The transfer part runs from `tx_bits` to the end of the program; before it
        // the device has not produced a single clock.
        if offset >= self.transfer_offset {
            SendError::Timeout
        } else {
            SendError::NoClock
        }
    }

    /// [`Ps2Port::next_event`].
    // Once in flash, not once per state machine.
    #[inline(never)]
    fn next_event(&mut self, sm: &mut dyn Machine, now_us: u64) -> Option<Ps2Event> {
        if self.stalled_words.is_none() && sm.rx_stalled() {
            // The words queued before the stall are whole frames: deliver them first.
            self.stalled_words = Some(sm.rx_level());
        }
        if let Some(left) = self.stalled_words {
            if left > 0 {
                self.stalled_words = Some(left - 1);
                if let Some(event) = self.pull_event(sm) {
                    return Some(event);
                }
            }
            // Bits went by while the program waited on its push: what it receives
            // now is not trustworthy. Start over on the next start bit.
            self.stalled_words = None;
            self.abandoned = self.send_deadline.take().is_some();
            self.restart(sm);
            return Some(Ps2Event::RxStall);
        }
        if self.abandoned {
            self.abandoned = false;
            return Some(Ps2Event::Sent(Err(SendError::Timeout)));
        }
        if let Some(event) = self.pull_event(sm) {
            return Some(event);
        }
        match self.send_deadline {
            Some(deadline) if now_us >= deadline => {
                let reason = self.stuck_reason(sm);
                self.send_deadline = None;
                self.restart(sm);
                Some(Ps2Event::Sent(Err(reason)))
            }
            _ => None,
        }
    }

    /// [`Ps2Port::line_fault`].
    // Once in flash, not once per state machine.
    #[inline(never)]
    fn line_fault(&self) -> Option<LineFault> {
        // The wire levels as the GPIOs read them (SIO input, bank 0).
        let levels = pac::SIO.gpio_in(0).read();
        let low = |pin: u8| levels & (1 << pin) == 0;
        if low(self.data_pin + 1) {
            Some(LineFault::ClockStuckLow)
        } else if low(self.data_pin) {
            Some(LineFault::DataStuckLow)
        } else {
            None
        }
    }

    /// [`Ps2Port::send`].
    // Once in flash, not once per state machine.
    #[inline(never)]
    fn send(&mut self, sm: &mut dyn Machine, frame: HostFrame, now_us: u64) {
        if self.send_deadline.take().is_some() {
            self.restart(sm);
        }
        // The program pulls the data line low for a 1 in the word: invert the levels.
        let word = COMMAND_MARK | u32::from(!frame.raw() & HOST_FRAME_MASK);
        // Nothing else is queued (one command at a time, FIFOs cleared on restart),
        // so the 4-word TX FIFO has room.
        sm.tx_push(word);
        self.send_deadline = Some(now_us + SEND_TIMEOUT_US);
    }
}

impl<PIO: Instance, const SM: usize> Ps2Port for PioPs2Port<'_, PIO, SM> {
    fn next_event(&mut self, now_us: u64) -> Option<Ps2Event> {
        self.core.next_event(&mut self.wire, now_us)
    }

    fn sending(&self) -> bool {
        self.core.send_deadline.is_some() || self.core.abandoned
    }

    fn line_fault(&self) -> Option<LineFault> {
        self.core.line_fault()
    }

    fn send(&mut self, frame: HostFrame, now_us: u64) {
        self.core.send(&mut self.wire, frame, now_us);
    }
}

/// The eight ports: 0..=3 on PIO0's state machines 0..=3, 4..=7 on PIO1's.
pub struct Ps2Ports {
    port0: PioPs2Port<'static, PIO0, 0>,
    port1: PioPs2Port<'static, PIO0, 1>,
    port2: PioPs2Port<'static, PIO0, 2>,
    port3: PioPs2Port<'static, PIO0, 3>,
    port4: PioPs2Port<'static, PIO1, 0>,
    port5: PioPs2Port<'static, PIO1, 1>,
    port6: PioPs2Port<'static, PIO1, 2>,
    port7: PioPs2Port<'static, PIO1, 3>,
    // Kept so the blocks' pin registrations and program memory stay owned.
    _common0: Common<'static, PIO0>,
    _common1: Common<'static, PIO1>,
}

impl Ps2Ports {
    /// Loads the program into both PIO blocks and starts all eight ports.
    pub fn new(
        pio0: Pio<'static, PIO0>,
        pio1: Pio<'static, PIO1>,
        pins: Ps2Pins,
        dma: Ps2Dma,
    ) -> Self {
        let Pio {
            common: mut common0,
            sm0: sm00,
            sm1: sm01,
            sm2: sm02,
            sm3: sm03,
            ..
        } = pio0;
        let Pio {
            common: mut common1,
            sm0: sm10,
            sm1: sm11,
            sm2: sm12,
            sm3: sm13,
            ..
        } = pio1;
        let program0 = Ps2Program::new(&mut common0);
        let program1 = Ps2Program::new(&mut common1);
        let (d0, c0) = pins.port0;
        let (d1, c1) = pins.port1;
        let (d2, c2) = pins.port2;
        let (d3, c3) = pins.port3;
        let (d4, c4) = pins.port4;
        let (d5, c5) = pins.port5;
        let (d6, c6) = pins.port6;
        let (d7, c7) = pins.port7;
        Self {
            port0: PioPs2Port::new(
                &mut common0,
                sm00,
                RxRing::new(dma.ch0, 0, 0, 0),
                &program0,
                d0,
                c0,
            ),
            port1: PioPs2Port::new(
                &mut common0,
                sm01,
                RxRing::new(dma.ch1, 1, 0, 1),
                &program0,
                d1,
                c1,
            ),
            port2: PioPs2Port::new(
                &mut common0,
                sm02,
                RxRing::new(dma.ch2, 2, 0, 2),
                &program0,
                d2,
                c2,
            ),
            port3: PioPs2Port::new(
                &mut common0,
                sm03,
                RxRing::new(dma.ch3, 3, 0, 3),
                &program0,
                d3,
                c3,
            ),
            port4: PioPs2Port::new(
                &mut common1,
                sm10,
                RxRing::new(dma.ch4, 4, 1, 0),
                &program1,
                d4,
                c4,
            ),
            port5: PioPs2Port::new(
                &mut common1,
                sm11,
                RxRing::new(dma.ch5, 5, 1, 1),
                &program1,
                d5,
                c5,
            ),
            port6: PioPs2Port::new(
                &mut common1,
                sm12,
                RxRing::new(dma.ch6, 6, 1, 2),
                &program1,
                d6,
                c6,
            ),
            port7: PioPs2Port::new(
                &mut common1,
                sm13,
                RxRing::new(dma.ch7, 7, 1, 3),
                &program1,
                d7,
                c7,
            ),
            _common0: common0,
            _common1: common1,
        }
    }

    /// The ports in port order.
    pub fn all(&mut self) -> [&mut dyn Ps2Port; PORTS] {
        [
            &mut self.port0,
            &mut self.port1,
            &mut self.port2,
            &mut self.port3,
            &mut self.port4,
            &mut self.port5,
            &mut self.port6,
            &mut self.port7,
        ]
    }
}
