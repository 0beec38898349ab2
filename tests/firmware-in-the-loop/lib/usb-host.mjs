// A USB host for rp2040js's device controller: bus reset, control transfers (setup,
// data and status stages, each transfer with a timeout), enumeration of the HID
// sensor board, and 1 ms frames: each starts with a start-of-frame (SOF: the frame
// number in SOF_RD and the DEV_SOF interrupt), the OUT endpoint gets queued reports,
// and the IN endpoint is polled by one IN token in the frame, at the frame's start or
// moved by the host's jitter (`setTokenTiming`: real host controllers, hubs and other
// devices on the bus move it). A token that finds no armed IN buffer is NAKed and
// counted (`naks`).
//
// rp2040js models the device side only: the device arming an IN buffer becomes
// `onEndpointWrite(ep, data)` 10 µs later, `sendSetupPacket` delivers a SETUP. The
// host intercepts buffer arming (`DPRAMUpdated`): OUT buffers stay armed until the
// host has data for them (`deliverOut`), and the interrupt IN buffer waits for the
// host's next 1 ms frame (see `install`).

const EP0_IN_BUFFER_CONTROL = 0x80;
const EP15_OUT_BUFFER_CONTROL = 0xfc;
const BUF_AVAILABLE = 1 << 10;
const FRAME_NS = 1_000_000;
const SOF_RD = 0x48;
const INTR_DEV_SOF = 1 << 17;
const EP_ABORT = 0x60;
const SIE_STATUS = 0x50;
const SIE_SUSPENDED = 1 << 4;
const SIE_RESUME = 1 << 11;

export const DESCRIPTOR = { DEVICE: 1, CONFIGURATION: 2, STRING: 3, INTERFACE: 4, ENDPOINT: 5, HID: 0x21, HID_REPORT: 0x22 };

export class UsbTimeout extends Error {}

function setupPacket(bmRequestType, bRequest, wValue, wIndex, wLength) {
  return Uint8Array.from([
    bmRequestType,
    bRequest,
    wValue & 0xff,
    wValue >> 8,
    wIndex & 0xff,
    wIndex >> 8,
    wLength & 0xff,
    wLength >> 8,
  ]);
}

export class UsbHost {
  /**
   * @param {import('./board.mjs').Board} board
   * @param {{ transferTimeoutUs?: number }} options
   */
  constructor(board, { transferTimeoutUs = 50_000 } = {}) {
    this.board = board;
    this.usb = board.rp.usbCtrl;
    this.transferTimeoutUs = transferTimeoutUs;
    this.enabled = false;
    this.resetDone = false;
    this.transfer = null;
    this.ep0OutArmed = false;
    this.inEndpoint = null;
    this.outEndpoint = null;
    this.pendingIn = null;
    this.outArmed = 0; // size the device armed on the OUT endpoint (0: not armed)
    this.outQueue = [];
    /** IN reports received: { timeUs, frame, data }. */
    this.inReports = [];
    this.outSent = [];
    this.frame = 0;
    /** Frames (SOF) run: from `startPolling` until a suspend or a re-enumeration. */
    this.framing = false;
    /** IN tokens are sent in the frames. */
    this.polling = false;
    /** IN tokens NAKed (no armed IN buffer, or the endpoint aborted): { timeUs, frame }. */
    this.naks = [];
    /** IN tokens sent. */
    this.tokens = 0;
    this.setTokenTiming({ kind: 'fixed' });
    this.install();
  }

  /**
   * Where in each frame the host sends its IN token:
   * - `{ kind: 'fixed' }`: at the frame's start (a host with no other traffic);
   * - `{ kind: 'uniform', maxUs }`: uniformly 0 … maxUs µs after it;
   * - `{ kind: 'steps', stepsUs }`: at one of these offsets, each as likely (a
   *   full-speed device behind a high-speed hub: 125 µs microframes);
   * and with `skipOneIn: n`, no token at all in one frame of n on average. Offsets come
   * from a seeded generator (`seed`), so a run is reproducible.
   */
  setTokenTiming({ kind, maxUs = 0, stepsUs = [0], skipOneIn = 0, seed = 1 }) {
    if (!['fixed', 'uniform', 'steps'].includes(kind)) {
      throw new Error(`unknown token timing ${kind}`);
    }
    this.tokenTiming = { kind, maxUs, stepsUs, skipOneIn };
    let state = seed >>> 0;
    // mulberry32: a small, well-mixed 32-bit generator.
    this.random = () => {
      state = (state + 0x6d2b79f5) >>> 0;
      let t = state;
      t = Math.imul(t ^ (t >>> 15), t | 1);
      t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
      return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
    };
  }

  /** This frame's token offset from its start (ns), or null for a skipped frame. */
  tokenOffsetNs() {
    const { kind, maxUs, stepsUs, skipOneIn } = this.tokenTiming;
    if (kind === 'fixed') {
      return 0;
    }
    if (skipOneIn > 0 && this.random() * skipOneIn < 1) {
      return null;
    }
    const us = kind === 'uniform' ? this.random() * maxUs : stepsUs[Math.floor(this.random() * stepsUs.length)];
    return Math.round(us * 1000);
  }

  install() {
    const usb = this.usb;
    usb.onUSBEnabled = () => {
      this.enabled = true;
    };
    usb.onResetReceived = () => {
      this.resetDone = true;
    };
    usb.onEndpointWrite = (endpoint, buffer) => this.onDeviceIn(endpoint, buffer);
    // Reading SOF_RD clears DEV_SOF on the RP2040; rp2040js has no device-side SOF.
    const readRegister = usb.readUint32.bind(usb);
    usb.readUint32 = (offset) => {
      const value = readRegister(offset);
      if (offset === SOF_RD && usb.intRaw & INTR_DEV_SOF) {
        usb.intRaw &= ~INTR_DEV_SOF;
        usb.checkInterrupts();
      }
      return value;
    };
    // Buffer arming. rp2040js clears AVAILABLE as soon as the firmware arms a
    // buffer; for OUT buffers that reads as "packet received" to a driver that
    // polls AVAILABLE (embassy-rp does), so OUT arming is kept here with AVAILABLE
    // still set until the host really sends (`deliverOut`). And the device's
    // interrupt IN buffer waits for the host's next frame.
    // EP_ABORT (the firmware revokes an armed IN buffer): rp2040js reports the abort
    // done at once; while an endpoint's bit is set the host's IN token is NAKed
    // (the pending buffer stays with the device), see `onFrame`.
    this.epAbort = 0;
    const writeRegister = usb.writeUint32.bind(usb);
    usb.writeUint32 = (offset, value) => {
      if (offset === EP_ABORT) {
        this.epAbort = value;
      }
      writeRegister(offset, value);
      // SIE_STATUS.SUSPENDED is write-one-to-clear on the RP2040; rp2040js keeps it.
      if (offset === SIE_STATUS && usb.rawWriteValue & SIE_SUSPENDED) {
        usb.sieStatus &= ~SIE_SUSPENDED;
        usb.sieStatusUpdated();
      }
    };
    const original = usb.DPRAMUpdated.bind(usb);
    this.releaseIn = original;
    this.armedOut = new Map(); // endpoint → buffer control offset
    usb.DPRAMUpdated = (offset, value) => {
      const inBufferControl = offset >= EP0_IN_BUFFER_CONTROL && offset <= EP15_OUT_BUFFER_CONTROL && !(offset & 4);
      if (inBufferControl && !(value & BUF_AVAILABLE) && (offset - EP0_IN_BUFFER_CONTROL) >> 3 === this.inEndpoint) {
        // The device disarmed its IN buffer (a revoke): nothing pending any more.
        this.pendingIn = null;
      }
      if (value & BUF_AVAILABLE && offset >= EP0_IN_BUFFER_CONTROL && offset <= EP15_OUT_BUFFER_CONTROL) {
        const endpoint = (offset - EP0_IN_BUFFER_CONTROL) >> 3;
        if (offset & 4) {
          this.armedOut.set(endpoint, offset);
          this.onDeviceOutArmed(endpoint, value & 0x3ff);
          return;
        }
        if (endpoint === this.inEndpoint) {
          this.pendingIn = { offset, value };
          return;
        }
      }
      original(offset, value);
    };
    this.frameAlarm = this.board.clock.createAlarm(() => this.onFrame());
    this.tokenAlarm = this.board.clock.createAlarm(() => this.onToken());
  }

  // ---- device → host callbacks ---------------------------------------------

  onDeviceIn(endpoint, buffer) {
    const data = Uint8Array.from(buffer);
    if (endpoint === 0) {
      const t = this.transfer;
      if (!t || t.done) {
        return;
      }
      if (t.stage === 'data-in') {
        t.data.push(...data);
        if (data.length < t.maxPacket || t.data.length >= t.length) {
          t.stage = 'status-out';
          this.tryStatusOut();
        }
      } else if (t.stage === 'status-in' && data.length === 0) {
        t.done = true;
      }
      return;
    }
    if (endpoint === this.inEndpoint) {
      this.inReports.push({ timeUs: this.board.timeUs, frame: this.frame, data });
      this.onReport?.(data);
    }
  }

  onDeviceOutArmed(endpoint, size) {
    if (endpoint === 0) {
      this.ep0OutArmed = true;
      const t = this.transfer;
      if (t && !t.done && t.stage === 'status-out') {
        this.tryStatusOut();
      } else if (t && !t.done && t.stage === 'data-out') {
        this.tryDataOut();
      }
      return;
    }
    if (endpoint === this.outEndpoint) {
      this.outArmed = size;
    }
  }

  /** The host sends `data` into the device's armed OUT buffer of `endpoint`. */
  deliverOut(endpoint, data) {
    const offset = this.armedOut.get(endpoint);
    this.armedOut.delete(endpoint);
    const view = this.board.rp.usbDPRAMView;
    view.setUint32(offset, view.getUint32(offset, true) & ~BUF_AVAILABLE, true);
    this.usb.finishRead(endpoint, data);
  }

  tryStatusOut() {
    const t = this.transfer;
    if (this.ep0OutArmed) {
      this.ep0OutArmed = false;
      this.deliverOut(0, new Uint8Array(0));
      t.done = true;
    }
  }

  tryDataOut() {
    const t = this.transfer;
    if (this.ep0OutArmed) {
      this.ep0OutArmed = false;
      this.deliverOut(0, t.out);
      t.stage = 'status-in';
    }
  }

  // ---- frames: interrupt endpoints -----------------------------------------

  /** Starts the 1 ms frames (SOF, OUT delivery) if they are not running, and the IN
   *  tokens in them. */
  startPolling() {
    this.polling = true;
    if (!this.framing) {
      this.framing = true;
      this.frameAlarm.schedule(FRAME_NS);
    }
  }

  /** Stops the IN tokens (the host's driver pauses); the frames go on (SOF, OUT). */
  stopPolling() {
    this.polling = false;
    this.tokenAlarm.cancel();
  }

  /** Stops the frames altogether (a suspended or reset bus). */
  stopFrames() {
    this.stopPolling();
    this.framing = false;
    this.frameAlarm.cancel();
  }

  onFrame() {
    this.frame++;
    this.usb.sofFrameNumber = this.frame & 0x7ff;
    this.usb.intRaw |= INTR_DEV_SOF;
    this.usb.checkInterrupts();
    if (this.outQueue.length > 0 && this.outArmed > 0) {
      const data = this.outQueue.shift();
      this.outArmed = 0;
      this.outSent.push({ timeUs: this.board.timeUs, data });
      this.deliverOut(this.outEndpoint, data);
    }
    if (this.polling) {
      const offset = this.tokenOffsetNs();
      if (offset === 0) {
        this.onToken();
      } else if (offset !== null) {
        this.tokenAlarm.schedule(offset);
      }
    }
    this.frameAlarm.schedule(FRAME_NS);
  }

  /** The host's IN token: the armed buffer is taken, or the token is NAKed. */
  onToken() {
    if (!this.polling) {
      return;
    }
    this.tokens++;
    const aborted = this.epAbort & (1 << (this.inEndpoint * 2));
    if (this.pendingIn && !aborted) {
      const { offset, value } = this.pendingIn;
      this.pendingIn = null;
      this.releaseIn(offset, value);
    } else {
      this.naks.push({ timeUs: this.board.timeUs, frame: this.frame });
    }
  }

  /**
   * Resets the bus and enumerates again, as a host does after resuming from sleep
   * or when its driver restarts the device: frames stop, whatever the device had
   * armed is gone, then the whole enumeration runs (see `enumerate`).
   */
  reenumerate(options) {
    this.stopFrames();
    this.pendingIn = null;
    this.outArmed = 0;
    this.ep0OutArmed = false;
    this.armedOut.clear();
    this.resetDone = false;
    return this.enumerate(options);
  }

  /** Suspends the bus: no more frames (no SOF, no IN tokens); the device sees the
   *  suspend state (SIE_STATUS.SUSPENDED, DEV_SUSPEND interrupt). */
  suspend() {
    this.stopFrames();
    this.usb.sieStatus |= SIE_SUSPENDED;
    this.usb.sieStatusUpdated();
  }

  /** Resume signalling from the host, then frames again. */
  resume() {
    this.usb.sieStatus |= SIE_RESUME;
    this.usb.sieStatusUpdated();
    this.startPolling();
  }

  /** Queues an OUT report for the interrupt OUT endpoint (sent at a frame). */
  sendOut(bytes) {
    this.outQueue.push(Uint8Array.from(bytes));
  }

  // ---- control transfers ---------------------------------------------------

  runTransfer(description) {
    const t = this.transfer;
    const ok = this.board.runUntil(() => t.done, this.transferTimeoutUs, 20);
    this.transfer = null;
    if (!ok) {
      throw new UsbTimeout(`USB ${description}: no completion within ${this.transferTimeoutUs} µs (stage ${t.stage})`);
    }
    return Uint8Array.from(t.data);
  }

  /** A control transfer with an IN data stage. */
  controlIn(bmRequestType, bRequest, wValue, wIndex, wLength, description) {
    this.transfer = { stage: 'data-in', data: [], length: wLength, maxPacket: this.maxPacket0 ?? 64, done: false };
    this.ep0OutArmed = false;
    this.usb.sendSetupPacket(setupPacket(bmRequestType, bRequest, wValue, wIndex, wLength));
    return this.runTransfer(description);
  }

  /** A control transfer with no data stage or an OUT data stage. */
  controlOut(bmRequestType, bRequest, wValue, wIndex, data, description) {
    const out = Uint8Array.from(data ?? []);
    this.transfer = { stage: out.length ? 'data-out' : 'status-in', data: [], out, done: false };
    this.ep0OutArmed = false;
    this.usb.sendSetupPacket(setupPacket(bmRequestType, bRequest, wValue, wIndex, out.length));
    if (out.length) {
      this.tryDataOut();
    }
    return this.runTransfer(description);
  }

  /** HID GET_REPORT (Feature, no report id) on the HID interface: `length` bytes. */
  getFeatureReport(length) {
    return this.controlIn(0xa1, 0x01, 0x0300, this.info.hid.number, length, 'GET_REPORT(Feature)');
  }

  /** HID SET_REPORT (Feature, no report id) on the HID interface. */
  setFeatureReport(bytes) {
    return this.controlOut(0x21, 0x09, 0x0300, this.info.hid.number, bytes, 'SET_REPORT(Feature)');
  }

  getDescriptor(type, index, length, wIndex = 0, recipient = 0x80) {
    return this.controlIn(recipient, 6, (type << 8) | index, wIndex, length, `GET_DESCRIPTOR(${type}, ${index})`);
  }

  // ---- enumeration ---------------------------------------------------------

  /**
   * Enumerates the device as a host would; returns what it learnt. Throws on a
   * timeout (every step is bounded) or a malformed descriptor.
   */
  enumerate({ address = 7, powerUpTimeoutUs = 500_000 } = {}) {
    const board = this.board;
    if (!board.runUntil(() => this.enabled, powerUpTimeoutUs)) {
      throw new UsbTimeout('USB: the device never enabled its controller');
    }
    // Bus reset (rp2040js: ~10 ms), then the device handles it.
    this.usb.resetDevice();
    if (!board.runUntil(() => this.resetDone, 50_000)) {
      throw new UsbTimeout('USB: bus reset not handled');
    }
    board.runUs(100);

    // Device descriptor at address 0 to learn bMaxPacketSize0 (as Linux does: ask
    // for 64 bytes with a 64-byte packet size; the 18-byte answer is one short packet).
    this.maxPacket0 = 64;
    const first = this.getDescriptor(DESCRIPTOR.DEVICE, 0, 64);
    if (first.length < 8 || first[1] !== DESCRIPTOR.DEVICE) {
      throw new Error(`bad device descriptor ${Buffer.from(first).toString('hex')}`);
    }
    this.maxPacket0 = first[7];

    this.controlOut(0x00, 5, address, 0, null, 'SET_ADDRESS');
    board.runUs(2000); // the device has 2 ms to take the address
    this.address = address;

    const device = this.getDescriptor(DESCRIPTOR.DEVICE, 0, 18);
    const view = new DataView(device.buffer);
    const info = {
      deviceDescriptor: device,
      bcdUSB: view.getUint16(2, true),
      maxPacket0: device[7],
      vendorId: view.getUint16(8, true),
      productId: view.getUint16(10, true),
      bcdDevice: view.getUint16(12, true),
      iManufacturer: device[14],
      iProduct: device[15],
      iSerial: device[16],
      numConfigurations: device[17],
    };

    const configHead = this.getDescriptor(DESCRIPTOR.CONFIGURATION, 0, 9);
    const totalLength = configHead[2] | (configHead[3] << 8);
    const config = this.getDescriptor(DESCRIPTOR.CONFIGURATION, 0, totalLength);
    info.configuration = parseConfiguration(config);
    info.maxPowerMa = config[8] * 2;

    const langs = this.getDescriptor(DESCRIPTOR.STRING, 0, 255);
    const langId = langs.length >= 4 ? langs[2] | (langs[3] << 8) : 0x0409;
    const string = (index) => {
      if (!index) {
        return null;
      }
      const d = this.getDescriptor(DESCRIPTOR.STRING, index, 255, langId);
      return Buffer.from(d.subarray(2, d[0])).toString('utf16le');
    };
    info.manufacturer = string(info.iManufacturer);
    info.product = string(info.iProduct);
    info.serial = string(info.iSerial);

    const hid = info.configuration.interfaces.find((i) => i.class === 3);
    if (!hid) {
      throw new Error('no HID interface');
    }
    info.hid = hid;
    // From here on the interrupt endpoints exist: IN data waits for the host's frames.
    this.inEndpoint = hid.endpoints.find((e) => e.address & 0x80)?.address & 0x0f;
    this.outEndpoint = hid.endpoints.find((e) => !(e.address & 0x80))?.address ?? null;

    this.controlOut(0x00, 9, info.configuration.value, 0, null, 'SET_CONFIGURATION');
    // SET_IDLE(0) as an OS's HID driver sends; then the HID report descriptor.
    this.controlOut(0x21, 0x0a, 0, hid.number, null, 'SET_IDLE');
    info.reportDescriptor = this.getDescriptor(DESCRIPTOR.HID_REPORT, 0, hid.reportDescriptorLength, hid.number, 0x81);

    this.info = info;
    return info;
  }
}

/** Parses a configuration descriptor set: interfaces, HID descriptors, endpoints. */
export function parseConfiguration(bytes) {
  const result = { value: bytes[5], attributes: bytes[7], interfaces: [] };
  let current = null;
  for (let at = 0; at + 2 <= bytes.length; ) {
    const length = bytes[at];
    const type = bytes[at + 1];
    if (length < 2 || at + length > bytes.length) {
      throw new Error(`malformed configuration descriptor at byte ${at}`);
    }
    const d = bytes.subarray(at, at + length);
    if (type === DESCRIPTOR.INTERFACE) {
      current = { number: d[2], alternate: d[3], numEndpoints: d[4], class: d[5], subclass: d[6], protocol: d[7], endpoints: [] };
      result.interfaces.push(current);
    } else if (type === DESCRIPTOR.HID && current) {
      current.hidVersion = d[2] | (d[3] << 8);
      current.reportDescriptorLength = d[7] | (d[8] << 8);
    } else if (type === DESCRIPTOR.ENDPOINT && current) {
      current.endpoints.push({ address: d[2], attributes: d[3], maxPacket: d[4] | (d[5] << 8), interval: d[6] });
    }
    at += length;
  }
  return result;
}
