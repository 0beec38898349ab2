// The UF2 a cabinet builder drags onto the board: its blocks are checked, and the
// flash image they describe is exactly the ELF's flash contents. (The main harness
// run, test/firmware.test.mjs, boots from this same UF2.)
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { Elf } from '../lib/elf.mjs';
import { FLASH_BASE } from '../lib/board.mjs';
import { firmwareElfPath, firmwareUf2Path } from '../lib/rig.mjs';
import { RP2040_FAMILY_ID, readUf2, writeUf2 } from '../lib/uf2.mjs';

/** The RP2040's flash window as `memory.x` maps it (2 MiB from 0x10000000). */
const FLASH = { flashBase: FLASH_BASE, flashBytes: 2048 * 1024 };

describe('the UF2 a builder flashes', () => {
  it('has valid blocks (magic numbers, RP2040 family id, 256-byte payloads in flash, numbered, no gaps)', (t) => {
    const path = firmwareUf2Path();
    const { blocks, start, image } = readUf2(new Uint8Array(readFileSync(path)), FLASH);
    assert.equal(start, FLASH_BASE, 'starts with boot2 at the start of flash');
    t.diagnostic(`${path}: ${blocks} blocks, 0x${start.toString(16)}..0x${(start + image.length).toString(16)}`);
  });

  it('holds exactly the ELF flash image (every loadable segment byte for byte, nothing else)', () => {
    const elf = new Elf(new Uint8Array(readFileSync(firmwareElfPath())));
    const { start, image } = readUf2(new Uint8Array(readFileSync(firmwareUf2Path())), FLASH);
    const segments = elf.loadSegments().filter((s) => s.address >= FLASH_BASE && s.address < FLASH_BASE + FLASH.flashBytes);
    assert.ok(segments.length >= 3, 'boot2, vector table + text, data load image');
    const expected = new Uint8Array(image.length);
    let end = 0;
    for (const { address, data } of segments) {
      const at = address - start;
      assert.ok(at >= 0 && at + data.length <= image.length, `segment at 0x${address.toString(16)} inside the UF2`);
      expected.set(data, at);
      end = Math.max(end, at + data.length);
    }
    assert.ok(image.length - end < 256, 'no more than the last page’s padding after the image');
    const firstDifference = image.findIndex((b, i) => b !== expected[i]);
    assert.equal(firstDifference, -1, `UF2 differs from the ELF at 0x${(start + firstDifference).toString(16)}`);
  });

  // The reader's checks can fail: each mutation of a good UF2 is rejected by name.
  const good = () => writeUf2(Uint8Array.from({ length: 1000 }, (_, i) => i & 0xff), FLASH_BASE);
  const word = (bytes, block, offset, value) => new DataView(bytes.buffer).setUint32(block * 512 + offset, value, true);
  const cases = [
    ['a bad start magic', (b) => word(b, 1, 0, 0x12345678), /bad start magic/],
    ['a bad end magic', (b) => word(b, 2, 508, 0), /bad end magic/],
    ['another family id', (b) => word(b, 0, 28, 0xe48bff57), /family id 0xe48bff57/],
    ['a missing family flag', (b) => word(b, 0, 8, 0), /flags 0x0/],
    ['a 476-byte payload', (b) => word(b, 3, 16, 476), /payload of 476 bytes/],
    ['a block number out of order', (b) => word(b, 2, 20, 3), /numbered 3 of 4, expected 2 of 4/],
    ['a wrong block count', (b) => word(b, 1, 24, 5), /numbered 1 of 5/],
    ['a gap between blocks', (b) => word(b, 2, 12, FLASH_BASE + 0x300), /expected 0x10000200 \(a gap or a repeat\)/],
    ['a target outside flash', (b) => word(b, 0, 12, 0x20000000), /outside flash/],
    ['a truncated file', (b) => b.subarray(0, 1000), /not a whole number/],
  ];
  for (const [what, mutate, message] of cases) {
    it(`rejects ${what}`, () => {
      const bytes = good();
      assert.doesNotThrow(() => readUf2(bytes, FLASH));
      const mutated = mutate(bytes) ?? bytes;
      assert.throws(() => readUf2(mutated, FLASH), message);
    });
  }

  it('the writer used by these tests marks blocks for the RP2040', () => {
    const bytes = good();
    assert.equal(new DataView(bytes.buffer).getUint32(28, true), RP2040_FAMILY_ID);
  });
});
