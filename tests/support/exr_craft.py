"""Crafted OpenEXR files for the damaged-input tests (issue 54): headers written byte by byte,
with any data window, compression and part layout, and chunk tables and chunks as given, so that
a header can claim what its bytes cannot hold."""
import struct

COMPRESSIONS = ["none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"]
LINES_PER_CHUNK = {"none": 1, "rle": 1, "zips": 1, "zip": 16, "pxr24": 16, "piz": 32, "b44": 32,
                   "b44a": 32, "dwaa": 32, "dwab": 256}


def attr(name, type_, value):
    return name.encode() + b"\0" + type_.encode() + b"\0" + struct.pack("<i", len(value)) + value


def header(window, compression, channels=("A", "B", "G", "R"), pixel_type=1, tiles=None,
           part_name=None, part_type=None, chunk_count=None):
    """One part's header attributes (without the terminating 0). window: (x0, y0, x1, y1)."""
    chl = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", pixel_type, 0, 1, 1) for c in channels) + b"\0"
    box = struct.pack("<4i", *window)
    h = attr("channels", "chlist", chl)
    h += attr("compression", "compression", bytes([COMPRESSIONS.index(compression)]))
    h += attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box)
    h += attr("lineOrder", "lineOrder", b"\0")
    h += attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    h += attr("screenWindowCenter", "v2f", struct.pack("<2f", 0, 0))
    h += attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    if tiles:
        h += attr("tiles", "tiledesc", struct.pack("<IIB", tiles[0], tiles[1], 0))
    if part_name is not None:
        h += attr("name", "string", part_name.encode())
        h += attr("type", "string", part_type.encode())
        h += attr("chunkCount", "int", struct.pack("<i", chunk_count))
    return h


def scanline_file(window, compression, chunks, table=None, **kw):
    """A single-part scanline file. chunks: [(first line, data bytes)]; table: the offset table's
    entries (default: where the chunks lie); entries beyond len(table) are cut off."""
    head = struct.pack("<II", 20000630, 2) + header(window, compression, **kw) + b"\0"
    n = len(chunks) if table is None else len(table)
    at = len(head) + 8 * n
    offsets, body = [], b""
    for y, data in chunks:
        offsets.append(at + len(body))
        body += struct.pack("<ii", y, len(data)) + data
    if table is not None:
        offsets = table
    return head + b"".join(struct.pack("<Q", o) for o in offsets) + body


def tiled_file(window, compression, tile, chunks, **kw):
    """A single-part tiled file (one level). chunks: [((tx, ty), data bytes)]."""
    head = struct.pack("<II", 20000630, 2 | 0x200) + header(window, compression, tiles=tile, **kw) + b"\0"
    at = len(head) + 8 * len(chunks)
    offsets, body = [], b""
    for (tx, ty), data in chunks:
        offsets.append(at + len(body))
        body += struct.pack("<4ii", tx, ty, 0, 0, len(data)) + data
    return head + b"".join(struct.pack("<Q", o) for o in offsets) + body


def multipart_file(parts):
    """parts: [(window, compression, channels, chunks)] scanline parts; chunks [(y, data)]."""
    heads = b""
    for i, (window, comp, chans, chunks) in enumerate(parts):
        heads += header(window, comp, channels=chans, part_name=f"part{i}", part_type="scanlineimage",
                        chunk_count=len(chunks)) + b"\0"
    head = struct.pack("<II", 20000630, 2 | 0x1000) + heads + b"\0"
    at = len(head) + 8 * sum(len(p[3]) for p in parts)
    offsets, body = [], b""
    for i, (_, _, _, chunks) in enumerate(parts):
        for y, data in chunks:
            offsets.append(at + len(body))
            body += struct.pack("<iii", i, y, len(data)) + data
    return head + b"".join(struct.pack("<Q", o) for o in offsets) + body


def damaged_corpus():
    """(name, bytes) of crafted damaged files under 1 KiB, for every compression (issue 54)."""
    big = (0, 0, 100663296, 0)
    data = bytes((i * 37) & 0xff for i in range(200))
    for comp in COMPRESSIONS:
        yield f"claims-{comp}", scanline_file(big, comp, [(0, data)])
        lpc = LINES_PER_CHUNK[comp]
        win = (0, 0, 7, 3 * lpc - 1)  # three chunks
        # Chunks of sizes a real file's could have (none: 8 RGBA halves exactly; b44: within 11:1),
        # so that each file is refused by the check it is made for.
        size = {"none": 64, "b44": 200, "b44a": 200}.get(comp, 40)
        chunks = [(k * lpc, data[:size]) for k in range(3)]
        good = scanline_file(win, comp, chunks)
        table = 8 + len(header(win, comp)) + 1  # the offset table follows the header
        offs = [int.from_bytes(good[table + 8 * k:table + 8 * k + 8], "little") for k in range(3)]
        yield f"table-cut-{comp}", good[:table + 8 + 4]  # one entry and half of the next
        yield f"offset-past-end-{comp}", scanline_file(win, comp, chunks, table=[offs[0], offs[1], 1 << 20])
        yield f"listed-twice-{comp}", scanline_file(win, comp, chunks, table=[offs[0], offs[0], offs[2]])
        yield f"tile-claims-{comp}", tiled_file((0, 0, 15999, 15999), comp, (16384, 16384), [((0, 0), data[:64])])


def write_corpus(folder):
    """Writes damaged_corpus() into folder (scripts/fuzz.sh: seeds for the EXR harness)."""
    import os
    os.makedirs(folder, exist_ok=True)
    for name, b in damaged_corpus():
        with open(os.path.join(folder, f"crafted-{name}.exr"), "wb") as f:
            f.write(b)


if __name__ == "__main__":
    import sys
    write_corpus(sys.argv[1])
