#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_tile_checkpoint (fuzz/corpus/tile_checkpoint/): render checkpoints
of the target's fixed shape (two sensors of 24 and 4 film values in 6 and 2 tiles, IR hash
1234567890123456789, every sensor selected), each packed as fuzz/targets/fuzz_folder.h describes.
The layout is render/tile_checkpoint.cpp's save(): state.json and sensor<k>-<generation>.f32."""
import json
import pathlib
import struct

IR_HASH = "1234567890123456789"
VALUES, SLOTS = [24, 4], [6, 2]


def packed(files):
    # "--- PATH\n" then the bytes, and the "\n" that ends them before the next header.
    return b"\n".join(b"--- " + name.encode() + b"\n" + data for name, data in files)


def checkpoint(generation, done, values=VALUES, extra=None, drop=None):
    state = {"format": "littoral-tile-checkpoint", "ir_hash": IR_HASH, "sensor": "", "generation": generation,
             "sensors": [{"values": v, "done": d} for v, d in zip(values, done)]}
    if extra:
        state.update(extra)
    files = [("state.json", (json.dumps(state, indent=1) + "\n").encode())]
    for k, v in enumerate(values):
        if k == drop:
            continue
        floats = [0.25 * i - 1.0 for i in range(v)]
        files.append((f"sensor{k}-{generation}.f32", struct.pack(f"<{v}f", *floats)))
    return packed(files)


seeds = {
    "first_chunk": checkpoint(1, ["110000", "00"]),
    "first_sensor_done": checkpoint(3, ["111111", "10"]),
    "all_done": checkpoint(7, ["111111", "11"]),
    "nothing_done": checkpoint(1, ["000000", "00"]),
    "values_file_missing": checkpoint(2, ["111000", "00"], drop=1),
    "wrong_shape": checkpoint(2, ["1110", "0"], values=[20, 4]),
}
out = pathlib.Path(__file__).resolve().parent / "corpus" / "tile_checkpoint"
out.mkdir(parents=True, exist_ok=True)
for name, data in seeds.items():
    (out / name).write_bytes(data)
print(f"{len(seeds)} seeds in {out}")
