// The USB report layouts of `protocol/` (foosball-protocol), for the harness.

/** Version of the OUT report (and of the v1 IN report). */
export const FORMAT_VERSION = 1;
/** Version of the IN report the firmware sends (`InReportV2`). */
export const IN_FORMAT_VERSION = 2;
export const PADDLES = 8;
/** The v2 IN report: version, sequence, device time (u32 µs), 7 bytes per paddle. */
export const IN_REPORT_LEN = 7 + 7 * PADDLES; // 63
/** `PacketAge` steps, µs; 255 = none that recent. */
export const PACKET_AGE_STEP_US = 100;
export const OUT_REPORT_LEN = 2 + 2 * PADDLES; // 18
/** `protocol/src/feature_report.rs`: every Feature report's length. */
export const FEATURE_REPORT_LEN = 56;

export const STATUS = {
  PRESENT: 0x01,
  AXIAL_OVERFLOW: 0x02,
  ROTATION_OVERFLOW: 0x04,
  FRAMING_ERROR: 0x08,
  PARITY_ERROR: 0x10,
  REINITIALISED: 0x20,
  SATURATED: 0x40,
};

export const LED = { OFF: 0, ON: 1, SLOW_BLINK: 2, FAST_BLINK: 3 };

/** `protocol/src/usb.rs`: ids, strings and the HID report descriptor. */
export const USB_IDS = {
  vendorId: 0x1209,
  productId: 0x0001,
  manufacturer: 'Space Foosball',
  product: 'Space Foosball sensor board',
};
export const HID_REPORT_DESCRIPTOR = Uint8Array.from([
  0x06, 0x00, 0xff, 0x09, 0x01, 0xa1, 0x01, 0x15, 0x00, 0x26, 0xff, 0x00, 0x75, 0x08, 0x09, 0x02,
  0x95, IN_REPORT_LEN, 0x81, 0x02, 0x09, 0x03, 0x95, OUT_REPORT_LEN, 0x91, 0x02,
  0x09, 0x04, 0x95, FEATURE_REPORT_LEN, 0xb1, 0x02, 0xc0,
]);

/**
 * Decodes a v2 IN report: { version, sequence, deviceTimeUs, paddles: [{ axial,
 * rotation, status, newestPacketAgeUs (null: none within 25.5 ms), dropped }] }.
 */
export function decodeInReport(bytes) {
  if (bytes.length !== IN_REPORT_LEN) {
    throw new Error(`IN report of ${bytes.length} bytes, expected ${IN_REPORT_LEN}`);
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const paddles = [];
  for (let i = 0; i < PADDLES; i++) {
    const at = 7 + 7 * i;
    const age = bytes[at + 5];
    paddles.push({
      axial: view.getInt16(at, true),
      rotation: view.getInt16(at + 2, true),
      status: bytes[at + 4],
      newestPacketAgeUs: age === 255 ? null : age * PACKET_AGE_STEP_US,
      dropped: bytes[at + 6],
    });
  }
  return { version: bytes[0], sequence: view.getUint16(1, true), deviceTimeUs: view.getUint32(3, true), paddles };
}

/** Encodes an OUT report: pulses [{ strength, durationMs }] per paddle, LED state. */
export function encodeOutReport(pulses, led = LED.ON, version = FORMAT_VERSION) {
  const out = new Uint8Array(OUT_REPORT_LEN);
  out[0] = version;
  for (let i = 0; i < PADDLES; i++) {
    out[1 + 2 * i] = pulses[i]?.strength ?? 0;
    out[2 + 2 * i] = pulses[i]?.durationMs ?? 0;
  }
  out[OUT_REPORT_LEN - 1] = led;
  return out;
}

/** `protocol/src/feature_report.rs`: the Feature report's version and kinds. */
export const FEATURE_VERSION = 1;
export const FEATURE_KIND = { DEVICE_INFO: 1, PORT_DIAGNOSTICS: 2, SETTINGS: 3, SELECT: 16, ENTER_BOOTLOADER: 17 };
export const RESET_REASON = { POWER_ON: 0, WATCHDOG_TIMEOUT: 1, FORCED: 2, PANIC: 3 };
const COUNTER_NAMES = [
  'frames', 'packets', 'framingErrors', 'parityErrors', 'resends', 'dropped',
  'retries', 'absences', 'inits', 'restarts', 'fifoStalls', 'lineFaults',
];

function featureHeader(kind) {
  const bytes = new Uint8Array(FEATURE_REPORT_LEN);
  bytes[0] = FEATURE_VERSION;
  bytes[1] = kind;
  return bytes;
}

/** A Select: the next GET_REPORT (Feature) returns `kind` (for port diagnostics, of `port`). */
export function encodeSelect(kind, port = 0) {
  const bytes = featureHeader(FEATURE_KIND.SELECT);
  bytes[2] = kind;
  bytes[3] = port;
  return bytes;
}

/** The restart-into-bootloader command (magic "BOOT"). */
export function encodeEnterBootloader() {
  const bytes = featureHeader(FEATURE_KIND.ENTER_BOOTLOADER);
  bytes.set([0x42, 0x4f, 0x4f, 0x54], 2);
  return bytes;
}

/** Settings: per port { axialIsY, invertAxial, invertRotation, resolutionCode, sampleRate }. */
export function encodeSettings(ports) {
  const bytes = featureHeader(FEATURE_KIND.SETTINGS);
  ports.forEach((p, i) => {
    bytes[2 + 3 * i] = (p.axialIsY ? 1 : 0) | (p.invertAxial ? 2 : 0) | (p.invertRotation ? 4 : 0);
    bytes[3 + 3 * i] = p.resolutionCode;
    bytes[4 + 3 * i] = p.sampleRate;
  });
  return bytes;
}

/** Decodes a Feature report the board sent (device info, port diagnostics or settings). */
export function decodeFeature(bytes) {
  if (bytes.length !== FEATURE_REPORT_LEN || bytes[0] !== FEATURE_VERSION) {
    throw new Error(`Feature report of ${bytes.length} bytes, version ${bytes[0]}`);
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  switch (bytes[1]) {
    case FEATURE_KIND.DEVICE_INFO:
      return {
        kind: 'deviceInfo',
        firmwareVersion: [bytes[2], bytes[3], bytes[4]],
        gitHash: Buffer.from(bytes.subarray(5, 17)).toString('latin1'),
        resetReason: bytes[17],
        uptimeUs: Number(view.getBigUint64(18, true)),
        presentPorts: bytes[26],
      };
    case FEATURE_KIND.PORT_DIAGNOSTICS: {
      const counters = {};
      COUNTER_NAMES.forEach((name, i) => {
        counters[name] = view.getUint32(8 + 4 * i, true);
      });
      return {
        kind: 'portDiagnostics',
        port: bytes[2],
        present: (bytes[3] & 1) !== 0,
        deviceId: bytes[3] & 2 ? bytes[4] : null,
        counters,
      };
    }
    case FEATURE_KIND.SETTINGS: {
      const ports = [];
      for (let i = 0; i < PADDLES; i++) {
        const flags = bytes[2 + 3 * i];
        ports.push({
          axialIsY: (flags & 1) !== 0,
          invertAxial: (flags & 2) !== 0,
          invertRotation: (flags & 4) !== 0,
          resolutionCode: bytes[3 + 3 * i],
          sampleRate: bytes[4 + 3 * i],
        });
      }
      return { kind: 'settings', ports };
    }
    default:
      throw new Error(`Feature report of kind ${bytes[1]}`);
  }
}
