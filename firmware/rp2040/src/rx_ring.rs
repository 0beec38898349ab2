//! Per-port receive rings: a DMA channel per PS/2 state machine copies every word the
//! state machine pushes into its RX FIFO (received frames and command completions)
//! into a ring of [`RING_WORDS`] words in RAM, as soon as it is pushed.
//!
//! The RX FIFO holds four words, a few milliseconds of traffic; the CPU can be away for
//! much longer: a flash sector erase runs with interrupts off for 45 ms typically and
//! 400 ms at most, in which eight mice at 200 samples/s send 240 frames each. The DMA
//! needs no CPU and reads neither flash nor XIP, so it goes on through the erase (and
//! embassy-rp's flash driver does not wait for it), and the ring holds 400 ms of a
//! mouse's frames.
//!
//! The channel's write address wraps at the ring's size (the DMA's address ring, the
//! ring aligned to its size); its transfer count counts down from `u32::MAX`, so the
//! words written are `u32::MAX − TRANS_COUNT` and the reader needs no interrupt. After
//! 2³² − 1 words (83 days of a mouse streaming) the channel stops and is started again
//! from where it is.

use core::ptr::{addr_of, read_volatile};
use core::sync::atomic::{compiler_fence, Ordering};

use embassy_rp::dma::ChannelInstance;
use embassy_rp::pac;
use embassy_rp::pac::dma::vals::{DataSize, TreqSel};
use embassy_rp::Peri;
use sensor_board::PORTS;

/// Words in one port's ring: 1 KiB, more than 400 ms of frames at the fastest
/// sample rate (200/s, three frames each).
pub const RING_WORDS: usize = 256;

/// log₂ of the ring's size in bytes: the DMA's write-address wrap.
const RING_SIZE_BITS: u8 = 10;
const _: () = assert!(RING_WORDS * 4 == 1 << RING_SIZE_BITS);

/// One ring, aligned to its size as the DMA's address wrap needs.
#[repr(C, align(1024))]
struct Ring([u32; RING_WORDS]);

/// The rings of the eight ports, written by DMA only.
static mut RINGS: [Ring; PORTS] = [const { Ring([0; RING_WORDS]) }; PORTS];

/// The RX side of one port: its DMA channel and its ring.
pub struct RxRing {
    /// DMA channel number.
    channel: usize,
    /// The ring's first word's address.
    ring: usize,
    /// The state machine's RX FIFO register.
    fifo: u32,
    dreq: TreqSel,
    /// Words the channel had written when it was last started.
    base: u32,
    /// Words read so far, counted like `written`.
    read: u32,
}

impl RxRing {
    /// Starts copying the RX FIFO of state machine `sm` of PIO block `pio` (0 or 1) into
    /// port `port`'s ring with DMA channel `channel`.
    pub fn new<C: ChannelInstance>(
        _channel: Peri<'static, C>,
        port: usize,
        pio: usize,
        sm: usize,
    ) -> Self {
        let (fifo, dreq) = match pio {
            0 => (
                pac::PIO0.rxf(sm).as_ptr() as u32,
                TreqSel::from(4 + sm as u8),
            ),
            _ => (
                pac::PIO1.rxf(sm).as_ptr() as u32,
                TreqSel::from(12 + sm as u8),
            ),
        };
        // SAFETY: only the address is taken; each port's ring is handed to one RxRing
        // (one per port, built once in `Ps2Ports::new`) and written by its DMA channel.
        let ring = unsafe { addr_of!(RINGS[port % PORTS].0) as usize };
        let mut rx = Self {
            channel: usize::from(C::number()),
            ring,
            fifo,
            dreq,
            base: 0,
            read: 0,
        };
        rx.start();
        rx
    }

    /// (Re)starts the channel: from the FIFO into the ring, where the write address
    /// stands, for `u32::MAX` words.
    fn start(&mut self) {
        let ch = pac::DMA.ch(self.channel);
        ch.read_addr().write_value(self.fifo);
        if self.base == 0 && self.read == 0 {
            ch.write_addr().write_value(self.ring as u32);
        }
        ch.trans_count().write_value(u32::MAX);
        let channel = self.channel as u8;
        let dreq = self.dreq;
        ch.ctrl_trig().write(|w| {
            w.set_en(true);
            w.set_data_size(DataSize::SIZE_WORD);
            w.set_incr_read(false);
            w.set_incr_write(true);
            w.set_ring_size(RING_SIZE_BITS);
            w.set_ring_sel(true);
            // Chained to itself: no chaining.
            w.set_chain_to(channel);
            w.set_treq_sel(dreq);
            w.set_irq_quiet(true);
        });
    }

    /// Words the channel has written since it was first started (wrapping).
    fn written(&mut self) -> u32 {
        let ch = pac::DMA.ch(self.channel);
        let remaining = ch.trans_count().read();
        if remaining == 0 && !ch.ctrl_trig().read().busy() {
            // 2³² − 1 words later: on from here.
            self.base = self.base.wrapping_add(u32::MAX);
            self.start();
            return self.base;
        }
        self.base.wrapping_add(u32::MAX - remaining)
    }

    /// Words waiting to be read (at most [`RING_WORDS`]: older ones were overwritten).
    pub fn level(&mut self) -> usize {
        (self.written().wrapping_sub(self.read) as usize).min(RING_WORDS)
    }

    /// The oldest word not yet read, if any; `Err` with the number of words lost when
    /// the ring overflowed since the last read (the reader goes on from the oldest word
    /// still there).
    pub fn pull(&mut self) -> Result<Option<u32>, u32> {
        let written = self.written();
        let waiting = written.wrapping_sub(self.read);
        if waiting as usize > RING_WORDS {
            let lost = waiting - RING_WORDS as u32;
            self.read = written.wrapping_sub(RING_WORDS as u32);
            return Err(lost);
        }
        if waiting == 0 {
            return Ok(None);
        }
        // The DMA's write completed before TRANS_COUNT counted it.
        compiler_fence(Ordering::Acquire);
        let index = self.read as usize % RING_WORDS;
        // SAFETY: `index` is within the ring; the word was written by the DMA before it
        // was counted, and the DMA writes it again only RING_WORDS words later.
        let word = unsafe { read_volatile((self.ring as *const u32).add(index)) };
        self.read = self.read.wrapping_add(1);
        Ok(Some(word))
    }

    /// Drops every word waiting (the state machine was restarted).
    pub fn clear(&mut self) {
        self.read = self.written();
    }
}
