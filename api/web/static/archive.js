// One file's text out of an archive the person chose (zip, tar, gzip'd tar), read in the
// browser so that an error message naming a file inside the archive can show its lines.
// Only what the page needs: stored and deflated zip entries, ustar names; null otherwise.
"use strict";

window.geomcheckArchive = (() => {
  const decoder = new TextDecoder();
  const ZIP_END = 0x06054b50;
  const ZIP_ENTRY = 0x02014b50;
  const ZIP_END_SEARCH = 22 + 0xffff; // the end record with the longest comment [bytes]
  const BLOCK = 512; // tar header and data blocks [bytes]

  function clean(name) {
    return name.replace(/^(\.\/)+/, "");
  }

  // archive entry `name` is the file a message calls `path` (report paths may add or drop a top folder)
  function matches(name, path) {
    return name === path || name.endsWith(`/${path}`) || path.endsWith(`/${name}`);
  }

  async function inflate(bytes, format) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream(format));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }

  async function fromZip(buffer, path) {
    const view = new DataView(buffer);
    let end = -1;
    for (let at = buffer.byteLength - 22; at >= Math.max(0, buffer.byteLength - ZIP_END_SEARCH); at -= 1) {
      if (view.getUint32(at, true) === ZIP_END) {
        end = at;
        break;
      }
    }
    if (end < 0) return null;
    const count = view.getUint16(end + 10, true);
    let at = view.getUint32(end + 16, true);
    for (let n = 0; n < count && at + 46 <= buffer.byteLength; n += 1) {
      if (view.getUint32(at, true) !== ZIP_ENTRY) return null;
      const method = view.getUint16(at + 10, true);
      const compressed = view.getUint32(at + 20, true);
      const nameLength = view.getUint16(at + 28, true);
      const skip = nameLength + view.getUint16(at + 30, true) + view.getUint16(at + 32, true);
      const local = view.getUint32(at + 42, true);
      const name = clean(decoder.decode(new Uint8Array(buffer, at + 46, nameLength)));
      at += 46 + skip;
      if (!matches(name, path)) continue;
      const start = local + 30 + view.getUint16(local + 26, true) + view.getUint16(local + 28, true);
      const data = new Uint8Array(buffer, start, Math.min(compressed, buffer.byteLength - start));
      if (method === 0) return decoder.decode(data);
      if (method === 8) return decoder.decode(await inflate(data, "deflate-raw"));
      return null;
    }
    return null;
  }

  function fromTar(bytes, path) {
    for (let at = 0; at + BLOCK <= bytes.length; ) {
      const header = bytes.subarray(at, at + BLOCK);
      if (header.every((b) => b === 0)) return null;
      const field = (from, length) => decoder.decode(header.subarray(from, from + length)).split("\0")[0];
      const size = parseInt(field(124, 12).trim() || "0", 8) || 0;
      const prefix = field(345, 155);
      const name = clean(prefix ? `${prefix}/${field(0, 100)}` : field(0, 100));
      const type = field(156, 1);
      const start = at + BLOCK;
      if ((type === "0" || type === "") && matches(name, path)) {
        return decoder.decode(bytes.subarray(start, start + size));
      }
      at = start + Math.ceil(size / BLOCK) * BLOCK;
    }
    return null;
  }

  // the text of the entry `path` names in the archive `file`, or null
  async function read(file, path) {
    const buffer = await file.arrayBuffer();
    const bytes = new Uint8Array(buffer);
    if (bytes[0] === 0x50 && bytes[1] === 0x4b) return fromZip(buffer, path);
    if (bytes[0] === 0x1f && bytes[1] === 0x8b) return fromTar(await inflate(bytes, "gzip"), path);
    return fromTar(bytes, path);
  }

  return { read };
})();
