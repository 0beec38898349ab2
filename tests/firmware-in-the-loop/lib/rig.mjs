// The whole test rig: the emulated board running the firmware ELF, eight PS/2
// mice on the pin map's GPIOs, a USB host, and edge recorders on the eight
// haptic PWM outputs.
import { existsSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { Board } from './board.mjs';
import { Ps2Mouse } from './ps2-mouse.mjs';
import { UsbHost } from './usb-host.mjs';
import { decodeInReport } from './reports.mjs';

const here = dirname(fileURLToPath(import.meta.url));
export const REPO_ROOT = resolve(here, '..', '..', '..');

/** `firmware/README.md`: port n data = GP2n, clock = GP2n+1. */
export const PS2_DATA_GPIO = [0, 2, 4, 6, 8, 10, 12, 14];
export const PS2_CLOCK_GPIO = [1, 3, 5, 7, 9, 11, 13, 15];
/** Haptic motor n's PWM output. */
export const HAPTIC_GPIO = [16, 17, 18, 19, 20, 21, 22, 28];
export const LED_GPIO = 25;

/** The firmware ELF: $FIRMWARE_ELF, else the release build in the target dir. */
export function firmwareElfPath() {
  if (process.env.FIRMWARE_ELF) {
    return resolve(process.env.FIRMWARE_ELF);
  }
  const targetDir = process.env.CARGO_TARGET_DIR
    ? resolve(REPO_ROOT, process.env.CARGO_TARGET_DIR)
    : join(REPO_ROOT, 'target');
  return join(targetDir, 'thumbv6m-none-eabi', 'release', 'foosball-firmware');
}

/** The UF2 made from the ELF: $FIRMWARE_UF2, else `<elf>.uf2` beside it. */
export function firmwareUf2Path(elfPath = firmwareElfPath()) {
  return process.env.FIRMWARE_UF2 ? resolve(process.env.FIRMWARE_UF2) : `${elfPath}.uf2`;
}

/**
 * @param {{ elfPath?: string, uf2Path?: string, printLog?: boolean,
 *           mouse?: (port: number) => object, uniqueId?: number[],
 *           flashImage?: Uint8Array, sramImage?: Uint8Array }} options
 *   mouse: extra `Ps2Mouse` options per port (clock, timing, sample clock)
 *   uf2Path: boot from this UF2's flash image (the ELF still gives the symbols)
 *   uniqueId, flashImage, sramImage: see `Board`
 */
export function createRig({
  elfPath = firmwareElfPath(),
  uf2Path,
  printLog = process.env.FITL_LOG !== '0',
  mouse = () => ({}),
  uniqueId,
  flashImage,
  sramImage,
} = {}) {
  if (!existsSync(elfPath)) {
    throw new Error(
      `firmware ELF not found at ${elfPath}; build it first: ` +
        'cargo build -p foosball-firmware --target thumbv6m-none-eabi --release',
    );
  }
  if (uf2Path && !existsSync(uf2Path)) {
    throw new Error(`firmware UF2 not found at ${uf2Path}; make it first: elf2uf2-rs ${elfPath} ${uf2Path}`);
  }
  const board = new Board(elfPath, {
    uf2Path,
    uniqueId,
    flashImage,
    sramImage,
    onLog: printLog
      ? (m) => console.log(`[fw ${(m.timeUs / 1000).toFixed(3).padStart(9)} ms] ${m.level.padEnd(5)} ${m.text}`)
      : undefined,
  });
  const mice = PS2_DATA_GPIO.map(
    (data, port) => new Ps2Mouse(board, { port, data, clock: PS2_CLOCK_GPIO[port], ...mouse(port) }),
  );
  const host = new UsbHost(board);
  const haptics = HAPTIC_GPIO.map((pin) => board.recordEdges(pin));
  const led = board.recordEdges(LED_GPIO);
  return {
    board,
    mice,
    host,
    haptics,
    led,
    /** Decoded IN reports received from index `since` on. */
    reports(since = 0) {
      return host.inReports.slice(since).map((r) => ({ ...decodeInReport(r.data), timeUs: r.timeUs }));
    },
  };
}
