// A PS/2 mouse on two open-drain wires, at the wire level (IBM PS/2 timing):
//
//  * device → host: the mouse clocks each 11-bit frame (start 0, 8 data LSB first,
//    odd parity, stop 1) at ~12.5 kHz, changing data in the middle of the clock's
//    high phase; it only starts while the clock is high and aborts the frame (and
//    sends it again later) if the host pulls the clock low meanwhile (inhibit);
//  * host → device: the mouse watches for request-to-send (the host released the
//    clock while holding data low), then generates the clock, samples each bit in
//    the clock's high phase (8 data, parity, stop) and acknowledges by pulling data
//    low during an 11th clock;
//  * commands: reset (0xFF → 0xFA, self-test, 0xAA 0x00), set sample rate (0xF3 n),
//    set resolution (0xE8 n), enable / disable reporting (0xF4 / 0xF5), read data
//    (0xEB → 0xFA + a packet), status request (0xE9 → 0xFA, flags, resolution,
//    rate), get id (0xF2), set defaults (0xF6), scaling (0xE6 / 0xE7), resend
//    (0xFE → the last packet again); a parity error or an unknown command → 0xFE;
//  * streaming: scripted motion (`move`) goes out in 3-byte packets at the sample
//    rate, each delta clamped to the 9-bit range;
//  * hot-plug: `unplug` releases both wires and goes silent; `plug` powers up again
//    (defaults, reporting off) and announces the self-test with 0xAA 0x00.

const US = 1000; // nanoseconds

export class Ps2Mouse {
  /**
   * @param {import('./board.mjs').Board} board
   * @param {{ port: number, data: number, clock: number, halfPeriodUs?: number,
   *           selfTestUs?: number, replyDelayUs?: number, sampleClock?: number,
   *           rtsDelayUs?: number, parityErrorRate?: number, seed?: number }} options
   *   sampleClock: the mouse's own time base relative to the board's (1.01 = its
   *   sample period is 1 % long), so its packets drift against the host's frames
   *   rtsDelayUs: how long after request-to-send the mouse starts clocking (PS/2:
   *   up to 15 ms); replyDelayUs: from a received command to its answer (≤ 20 ms)
   *   parityErrorRate: fraction of the frames it sends with the parity bit flipped
   *   (a deterministic generator seeded with `seed`)
   *   clockGlitchRate: fraction of the frames it sends with a glitch on the clock
   *   line: one `glitchUs` low pulse (default 2 µs) in the high phase after a bit
   */
  constructor(
    board,
    {
      port,
      data,
      clock,
      halfPeriodUs = 40,
      selfTestUs = 5000,
      replyDelayUs = 150,
      sampleClock = 1,
      rtsDelayUs = halfPeriodUs,
      parityErrorRate = 0,
      clockGlitchRate = 0,
      glitchUs = 2,
      seed = 1,
    },
  ) {
    this.board = board;
    this.port = port;
    this.dataPin = data;
    this.clockPin = clock;
    this.half = halfPeriodUs * US;
    this.selfTestNs = selfTestUs * US;
    this.replyDelayNs = replyDelayUs * US;
    this.sampleClock = sampleClock;
    this.rtsDelayNs = rtsDelayUs * US;
    this.parityErrorRate = parityErrorRate;
    this.clockGlitchRate = clockGlitchRate;
    this.glitchNs = glitchUs * US;
    /** Frames sent with a clock glitch. */
    this.clockGlitchesSent = 0;
    this.random = seed >>> 0 || 1;
    /** Frames sent with a flipped parity bit. */
    this.parityErrorsSent = 0;
    /** Frames still to send at the burst clock (`sendBurst`). */
    this.burst = { bytes: 0, halfNs: this.half };
    /** Busy in its self-test until then: request-to-send goes unanswered. */
    this.busyUntilNs = 0;
    board.attachWire(data);
    board.attachWire(clock, () => this.onClockChange());

    this.plugged = true;
    this.defaults();
    /** Every byte the host sent: { byte, timeUs, parityOk, inhibitUs } (inhibitUs:
     *  how long the host held the clock low before its request-to-send). */
    this.received = [];
    /** Every byte this mouse finished sending: { byte, timeUs }. */
    this.sent = [];
    /** Motion sent in packets since the last `takeSentMotion`. */
    this.sentMotion = { dx: 0, dy: 0 };
    this.pending = { dx: 0, dy: 0 };
    this.outQueue = [];
    this.delayed = []; // [{ atNs, bytes }]
    this.lastPacketNs = -Infinity;
    /** Every stream packet sent: { dx, dy, endUs } (endUs: its last bit left the
     *  wire, i.e. the data line's release after the third frame's stop bit). */
    this.packets = [];
    this.streamPacket = null; // the queued stream packet's motion until it is sent
    this.lastFrameEndNs = null;

    this.hostClockLowSince = null;
    this.lastInhibitUs = null;
    this.alarm = board.clock.createAlarm(() => this.resume());
    this.proc = null;
    this.idle = false;
    this.start();
  }

  defaults() {
    this.streaming = false;
    this.sampleRate = 100;
    this.resolution = 2;
    this.expectArgument = null;
  }

  // ---- scripting -----------------------------------------------------------

  /** Scripted motion: sent in the next packets (mouse x, y counts). */
  move(dx, dy) {
    this.pending.dx += dx;
    this.pending.dy += dy;
    this.wake();
  }

  /** Pulls the plug: both wires released, nothing more sent or answered. */
  unplug() {
    this.plugged = false;
    this.alarm.cancel();
    this.proc = null;
    this.outQueue = [];
    this.delayed = [];
    this.board.setDeviceLow(this.dataPin, false);
    this.board.setDeviceLow(this.clockPin, false);
  }

  /**
   * Restarts (a brown-out): power-on defaults, busy for the self-test, then its
   * announcement — with the 0xAA lost on the wire when `loseSelfTestByte`.
   */
  restart({ loseSelfTestByte = false } = {}) {
    this.defaults();
    this.outQueue = [];
    this.streamPacket = null;
    this.busyUntilNs = this.board.timeNs + this.selfTestNs;
    this.delayed = [{ atNs: this.busyUntilNs, bytes: loseSelfTestByte ? [0x00] : [0xaa, 0x00] }];
    this.start();
  }

  /**
   * Sends `bytes` back to back at a clock far beyond PS/2's (`halfPeriodUs` per
   * phase, a few µs): faster than the firmware drains its 4-word RX FIFO, so the
   * receiver overflows. Not something a mouse does; a way to make the FIFO stall.
   */
  sendBurst(bytes, halfPeriodUs) {
    this.burst = { bytes: bytes.length, halfNs: halfPeriodUs * US };
    this.outQueue.push(...bytes);
    this.wake();
  }

  /** xorshift32: the next pseudo-random number in [0, 1). */
  nextRandom() {
    let x = this.random;
    x ^= x << 13;
    x ^= x >>> 17;
    x ^= x << 5;
    this.random = x >>> 0;
    return this.random / 2 ** 32;
  }

  /** Plugs the mouse back in: power-up defaults, then 0xAA 0x00 after the self-test. */
  plug() {
    this.plugged = true;
    this.defaults();
    this.pending = { dx: 0, dy: 0 };
    this.delayed.push({ atNs: this.board.timeNs + this.selfTestNs, bytes: [0xaa, 0x00] });
    this.start();
  }

  takeSentMotion() {
    const motion = this.sentMotion;
    this.sentMotion = { dx: 0, dy: 0 };
    return motion;
  }

  /** The command bytes received since index `since` (bytes only). */
  commands(since = 0) {
    return this.received.slice(since).map((r) => r.byte);
  }

  // ---- the process ---------------------------------------------------------

  start() {
    this.alarm.cancel();
    this.proc = this.main();
    this.idle = false;
    this.alarm.schedule(0);
  }

  /** Runs the process until its next wait. Yields: a number = wait that many ns;
   *  { untilNs } = wait until then or until woken (wire change, move, plug). */
  resume() {
    if (!this.proc) {
      return;
    }
    this.idle = false;
    const { value, done } = this.proc.next();
    if (done) {
      this.proc = null;
      return;
    }
    if (typeof value === 'number') {
      this.alarm.schedule(value);
    } else {
      this.idle = true;
      if (Number.isFinite(value.untilNs)) {
        this.alarm.schedule(Math.max(0, value.untilNs - this.board.timeNs));
      }
    }
  }

  wake() {
    if (this.proc && this.idle) {
      this.idle = false;
      this.alarm.schedule(0);
    }
  }

  onClockChange() {
    // How long the host holds the clock low before a request-to-send (≥ 100 µs).
    const now = this.board.timeNs;
    if (this.board.boardPullsLow(this.clockPin)) {
      this.hostClockLowSince ??= now;
    } else if (this.hostClockLowSince !== null) {
      this.lastInhibitUs = (now - this.hostClockLowSince) / US;
      this.hostClockLowSince = null;
    }
    this.wake();
  }

  clockHigh() {
    return this.board.wireLevel(this.clockPin);
  }

  dataHigh() {
    return this.board.wireLevel(this.dataPin);
  }

  /** Request-to-send: the host released the clock while holding data low. */
  requestToSend() {
    return this.clockHigh() && this.board.boardPullsLow(this.dataPin);
  }

  *main() {
    for (;;) {
      if (!this.plugged) {
        return;
      }
      const now = this.board.timeNs;
      if (this.requestToSend() && now >= this.busyUntilNs) {
        yield* this.receiveByte();
        continue;
      }
      // Delayed replies (self-test) that are due.
      for (let i = 0; i < this.delayed.length; ) {
        if (this.delayed[i].atNs <= now) {
          this.outQueue.push(...this.delayed[i].bytes);
          this.delayed.splice(i, 1);
        } else {
          i++;
        }
      }
      if (this.outQueue.length > 0) {
        if (!this.clockHigh()) {
          // Inhibited by the host: wait for the clock to come back.
          yield { untilNs: Infinity };
          continue;
        }
        const sent = yield* this.sendByte(this.outQueue[0]);
        if (sent) {
          this.sent.push({ byte: this.outQueue.shift(), timeUs: this.board.timeUs });
          if (this.outQueue.length === 0 && this.streamPacket) {
            const { dx, dy, bytes } = this.streamPacket;
            this.packets.push({ dx, dy, endUs: this.lastFrameEndNs / US });
            this.lastPacketBytes = bytes; // what a resend (0xFE) repeats
            this.streamPacket = null;
          }
        }
        continue;
      }
      const period = (1e9 / this.sampleRate) * this.sampleClock;
      const moving = this.pending.dx !== 0 || this.pending.dy !== 0;
      if (this.streaming && moving && now >= this.lastPacketNs + period) {
        this.lastPacketNs = now;
        const bytes = this.packet();
        this.streamPacket = { dx: this.lastPacket.dx, dy: this.lastPacket.dy, bytes };
        this.outQueue.push(...bytes);
        continue;
      }
      let untilNs = Infinity;
      if (this.streaming && moving) {
        untilNs = this.lastPacketNs + period;
      }
      for (const { atNs } of this.delayed) {
        untilNs = Math.min(untilNs, atNs);
      }
      yield { untilNs };
    }
  }

  /** The next movement packet: deltas clamped to −255..=255, taken from `pending`. */
  packet() {
    const clamp = (v) => Math.max(-255, Math.min(255, v));
    const dx = clamp(this.pending.dx);
    const dy = clamp(this.pending.dy);
    this.pending.dx -= dx;
    this.pending.dy -= dy;
    this.sentMotion.dx += dx;
    this.sentMotion.dy += dy;
    this.lastPacket = { dx, dy };
    const status = 0x08 | (dx < 0 ? 0x10 : 0) | (dy < 0 ? 0x20 : 0);
    return [status, dx & 0xff, dy & 0xff];
  }

  /** Sends one frame; false if the host inhibited it (it stays queued). */
  *sendByte(byte) {
    const bits = [0];
    let ones = 0;
    for (let i = 0; i < 8; i++) {
      const bit = (byte >> i) & 1;
      bits.push(bit);
      ones += bit;
    }
    let parity = ones % 2 === 0 ? 1 : 0;
    if (this.parityErrorRate > 0 && this.nextRandom() < this.parityErrorRate) {
      parity ^= 1;
      this.parityErrorsSent++;
    }
    bits.push(parity, 1);
    // The bit after which the clock glitches, if any.
    let glitchAfter = -1;
    if (this.clockGlitchRate > 0 && this.nextRandom() < this.clockGlitchRate) {
      glitchAfter = Math.floor(this.nextRandom() * 10);
      this.clockGlitchesSent++;
    }
    const board = this.board;
    // A burst (out of spec) runs at its own clock.
    const half = this.burst.bytes > 0 ? this.burst.halfNs : this.half;
    for (const [i, bit] of bits.entries()) {
      board.setDeviceLow(this.dataPin, bit === 0);
      yield half / 2;
      if (!this.clockHigh()) {
        board.setDeviceLow(this.dataPin, false);
        return false;
      }
      board.setDeviceLow(this.clockPin, true);
      yield half;
      board.setDeviceLow(this.clockPin, false);
      if (i === glitchAfter) {
        // Noise: a short low pulse on the clock in its high phase.
        yield half / 4;
        board.setDeviceLow(this.clockPin, true);
        yield this.glitchNs;
        board.setDeviceLow(this.clockPin, false);
        yield half / 4 - this.glitchNs;
      } else {
        yield half / 2;
      }
    }
    board.setDeviceLow(this.dataPin, false);
    this.lastFrameEndNs = board.timeNs;
    // Gap before the next frame.
    yield half;
    if (this.burst.bytes > 0) {
      this.burst.bytes--;
    }
    return true;
  }

  /** Clocks in one host-to-device frame after request-to-send and acknowledges it. */
  *receiveByte() {
    const board = this.board;
    const inhibitUs = this.lastInhibitUs;
    yield this.rtsDelayNs; // the device starts clocking within 15 ms
    const bits = [];
    for (let i = 0; i < 10; i++) {
      board.setDeviceLow(this.clockPin, true);
      yield this.half;
      board.setDeviceLow(this.clockPin, false);
      yield this.half / 2;
      if (!this.clockHigh()) {
        // The host holds the clock: transfer abandoned.
        return;
      }
      bits.push(this.dataHigh() ? 1 : 0);
      if (i === 9) {
        // Acknowledge: data low, an 11th clock, then release.
        board.setDeviceLow(this.dataPin, true);
      }
      yield this.half / 2;
    }
    board.setDeviceLow(this.clockPin, true);
    yield this.half;
    board.setDeviceLow(this.clockPin, false);
    yield this.half / 2;
    board.setDeviceLow(this.dataPin, false);

    let byte = 0;
    let ones = 0;
    for (let i = 0; i < 8; i++) {
      byte |= bits[i] << i;
      ones += bits[i];
    }
    const parityOk = (ones + bits[8]) % 2 === 1;
    this.received.push({ byte, timeUs: board.timeUs, parityOk, inhibitUs });
    // A command cancels whatever the mouse was about to send. A stream packet cut
    // short is sent again if the command is a resend, else its motion goes back
    // into the counters (as a mouse keeps its motion).
    const interrupted = this.streamPacket;
    this.streamPacket = null;
    this.outQueue = [];
    const resend = parityOk && bits[9] === 1 && byte === 0xfe && !this.expectArgument;
    if (interrupted && !resend) {
      this.pending.dx += interrupted.dx;
      this.pending.dy += interrupted.dy;
      this.sentMotion.dx -= interrupted.dx;
      this.sentMotion.dy -= interrupted.dy;
    }
    this.interrupted = resend ? interrupted : null;
    yield this.replyDelayNs;
    if (!parityOk || bits[9] !== 1) {
      this.outQueue.push(0xfe);
      return;
    }
    this.command(byte);
  }

  command(byte) {
    const reply = (...bytes) => this.outQueue.push(...bytes);
    if (this.expectArgument) {
      const which = this.expectArgument;
      this.expectArgument = null;
      if (which === 0xf3) {
        this.sampleRate = byte;
      } else {
        this.resolution = byte;
      }
      reply(0xfa);
      return;
    }
    switch (byte) {
      case 0xff: // reset
        this.defaults();
        this.delayed = [];
        reply(0xfa);
        this.delayed.push({ atNs: this.board.timeNs + this.selfTestNs, bytes: [0xaa, 0x00] });
        break;
      case 0xf3: // set sample rate
      case 0xe8: // set resolution
        this.expectArgument = byte;
        reply(0xfa);
        break;
      case 0xf4:
        this.streaming = true;
        reply(0xfa);
        break;
      case 0xf5:
        this.streaming = false;
        reply(0xfa);
        break;
      case 0xf6:
        this.defaults();
        reply(0xfa);
        break;
      case 0xeb: // read data: acknowledge, then a packet (with any pending motion)
        reply(0xfa, ...this.packet());
        break;
      case 0xf2: // get device id
        reply(0xfa, 0x00);
        break;
      case 0xe6:
      case 0xe7:
        reply(0xfa);
        break;
      case 0xfe: // resend: the packet cut short, else the last one, again (no acknowledge)
        if (this.interrupted) {
          this.streamPacket = this.interrupted;
          reply(...this.interrupted.bytes);
        } else {
          reply(...(this.lastPacketBytes ?? [0x08, 0x00, 0x00]));
        }
        this.interrupted = null;
        break;
      case 0xe9: // status request: acknowledge, flags, resolution, sample rate
        reply(0xfa, this.streaming ? 0x20 : 0, this.resolution, this.sampleRate);
        break;
      default:
        reply(0xfe);
    }
  }
}
