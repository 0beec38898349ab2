// UF2, the file a builder drags onto the RP2040's boot drive: 512-byte blocks,
// each carrying 256 bytes for one flash address (Microsoft's UF2 specification;
// the RP2040 bootrom takes blocks with the family id below and 256-byte payloads).
//
// `readUf2` checks every block and returns the flash image it describes; it throws
// an error naming the first problem found.

export const UF2_MAGIC_START0 = 0x0a324655; // "UF2\n"
export const UF2_MAGIC_START1 = 0x9e5d5157;
export const UF2_MAGIC_END = 0x0ab16f30;
export const UF2_FLAG_FAMILY_ID_PRESENT = 0x00002000;
export const UF2_FLAG_NOT_MAIN_FLASH = 0x00000001;
export const RP2040_FAMILY_ID = 0xe48bff56;
const BLOCK_BYTES = 512;
const PAYLOAD_BYTES = 256;
const DATA_OFFSET = 32;

/**
 * @param {Uint8Array} bytes the UF2 file
 * @param {{ flashBase: number, flashBytes: number }} flash the target's flash window
 * @returns {{ blocks: number, start: number, image: Uint8Array }} the contiguous
 *   image from `start` (the lowest target address), `blocks` blocks long
 */
export function readUf2(bytes, { flashBase, flashBytes }) {
  if (bytes.length === 0 || bytes.length % BLOCK_BYTES !== 0) {
    throw new Error(`UF2 of ${bytes.length} bytes: not a whole number of ${BLOCK_BYTES}-byte blocks`);
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const count = bytes.length / BLOCK_BYTES;
  let start = null;
  const image = new Uint8Array(count * PAYLOAD_BYTES);
  for (let i = 0; i < count; i++) {
    const at = i * BLOCK_BYTES;
    const word = (offset) => view.getUint32(at + offset, true);
    const where = `UF2 block ${i}`;
    if (word(0) !== UF2_MAGIC_START0 || word(4) !== UF2_MAGIC_START1) {
      throw new Error(`${where}: bad start magic 0x${word(0).toString(16)} 0x${word(4).toString(16)}`);
    }
    if (word(BLOCK_BYTES - 4) !== UF2_MAGIC_END) {
      throw new Error(`${where}: bad end magic 0x${word(BLOCK_BYTES - 4).toString(16)}`);
    }
    const flags = word(8);
    if (!(flags & UF2_FLAG_FAMILY_ID_PRESENT) || flags & UF2_FLAG_NOT_MAIN_FLASH) {
      throw new Error(`${where}: flags 0x${flags.toString(16)} (want the family id present, main flash)`);
    }
    const family = word(28);
    if (family !== RP2040_FAMILY_ID) {
      throw new Error(`${where}: family id 0x${family.toString(16)}, the RP2040's is 0x${RP2040_FAMILY_ID.toString(16)}`);
    }
    const payload = word(16);
    if (payload !== PAYLOAD_BYTES) {
      throw new Error(`${where}: payload of ${payload} bytes (the RP2040 bootrom takes ${PAYLOAD_BYTES})`);
    }
    const blockNo = word(20);
    const numBlocks = word(24);
    if (blockNo !== i || numBlocks !== count) {
      throw new Error(`${where}: numbered ${blockNo} of ${numBlocks}, expected ${i} of ${count}`);
    }
    const target = word(12);
    if (target % PAYLOAD_BYTES !== 0) {
      throw new Error(`${where}: target 0x${target.toString(16)} not on a ${PAYLOAD_BYTES}-byte page`);
    }
    if (target < flashBase || target + PAYLOAD_BYTES > flashBase + flashBytes) {
      throw new Error(`${where}: target 0x${target.toString(16)} outside flash`);
    }
    if (i === 0) {
      start = target;
    } else if (target !== start + i * PAYLOAD_BYTES) {
      throw new Error(
        `${where}: target 0x${target.toString(16)}, expected 0x${(start + i * PAYLOAD_BYTES).toString(16)} (a gap or a repeat)`,
      );
    }
    image.set(bytes.subarray(at + DATA_OFFSET, at + DATA_OFFSET + PAYLOAD_BYTES), i * PAYLOAD_BYTES);
  }
  return { blocks: count, start, image };
}

/** Builds a UF2 (for the reader's own tests): `image` from `start`, padded to pages. */
export function writeUf2(image, start, family = RP2040_FAMILY_ID) {
  const count = Math.ceil(image.length / PAYLOAD_BYTES);
  const bytes = new Uint8Array(count * BLOCK_BYTES);
  const view = new DataView(bytes.buffer);
  for (let i = 0; i < count; i++) {
    const at = i * BLOCK_BYTES;
    view.setUint32(at, UF2_MAGIC_START0, true);
    view.setUint32(at + 4, UF2_MAGIC_START1, true);
    view.setUint32(at + 8, UF2_FLAG_FAMILY_ID_PRESENT, true);
    view.setUint32(at + 12, start + i * PAYLOAD_BYTES, true);
    view.setUint32(at + 16, PAYLOAD_BYTES, true);
    view.setUint32(at + 20, i, true);
    view.setUint32(at + 24, count, true);
    view.setUint32(at + 28, family, true);
    bytes.set(image.subarray(i * PAYLOAD_BYTES, (i + 1) * PAYLOAD_BYTES), at + DATA_OFFSET);
    view.setUint32(at + BLOCK_BYTES - 4, UF2_MAGIC_END, true);
  }
  return bytes;
}
