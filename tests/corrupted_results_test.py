#!/usr/bin/python3
"""A flipped bit in a results file is refused by every reader, naming the file and the object
(issue 38, item 5: one flip doubled eps_p[5], and export, run --resume, merge and plot took it):
a byte of a dataset's stored values (found with h5py's chunk info), of the plan's text (an
attribute, in the file's global heap), and of a shard's values given to merge; a global heap
damaged where HDF5 itself would crash on it. A file without checksums (written before them) is
read with a note.

Usage: corrupted_results_test.py IMPACTID SOURCE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py


def run(*args):
    return subprocess.run(list(map(str, args)), capture_output=True, text=True)


def data_offset(path, name, index, itemsize=8):
    """The file offset of element `index` of dataset `name` (chunked: its first chunk)."""
    with h5py.File(path, "r") as f:
        d = f[name]
        if d.chunks is None:
            return d.id.get_offset() + index * itemsize
        info = d.id.get_chunk_info(0)
        assert d.compression is None, "the test flips an uncompressed chunk"
        return info.byte_offset + index * itemsize


def flip(path, offset, mask=0x10):
    with open(path, "r+b") as f:
        f.seek(offset)
        byte = f.read(1)[0]
        f.seek(offset)
        f.write(bytes([byte ^ mask]))


def damage_global_heap(path, length=1 << 40):
    """Sets the length of the first object of the file's first global heap collection ("GCOL":
    signature, version, 3 reserved, collection size; then per object its index, reference
    count, 4 reserved and its length, at +24) to `length`."""
    image = bytearray(open(path, "rb").read())
    at = image.find(b"GCOL")
    assert at >= 0, f"{path}: no global heap"
    image[at + 24:at + 32] = length.to_bytes(8, "little")
    with open(path, "wb") as f:
        f.write(image)


def main():
    impactid, source = sys.argv[1], sys.argv[2]
    plan = os.path.join(source, "plans", "demo.toml")
    failures = []

    def refused(what, done, *words):
        if done.returncode == 0 or any(w not in done.stderr for w in words):
            failures.append(f"{what}: not refused as expected (exit {done.returncode}, wanted "
                            f"{words}):\n{done.stdout[-1000:]}{done.stderr[-2000:]}")

    with tempfile.TemporaryDirectory() as tmp:
        good = os.path.join(tmp, "good.h5")
        made = run(impactid, "run", plan, "--output", good)
        if made.returncode != 0:
            print(f"run failed:\n{made.stderr[-2000:]}")
            print("corrupted_results_test: 1 failure(s)")
            return 1
        with h5py.File(good, "r") as f:
            if not f["eps_p"].fletcher32:
                failures.append("eps_p is stored without a Fletcher32 checksum")

        # One bit of eps_p[5]'s exponent: the value doubles or halves.
        bad = os.path.join(tmp, "bad.h5")
        shutil.copy(good, bad)
        flip(bad, data_offset(bad, "eps_p", 5) + 7, 0x01)
        before = open(bad, "rb").read()
        words = (bad, "eps_p", "data corrupted")
        refused("export", run(impactid, "export", bad, "--csv", os.path.join(tmp, "csv")), *words)
        refused("run --resume", run(impactid, "run", plan, "--output", bad, "--resume"), *words)
        if open(bad, "rb").read() != before:
            failures.append("run --resume changed the corrupted file")
        refused("plot", run(impactid, "plot", bad, "--out", os.path.join(tmp, "figures")), *words)

        # The plan's text, an attribute kept in the global heap: the checksum of the text.
        text = os.path.join(tmp, "text.h5")
        shutil.copy(good, text)
        image = open(text, "rb").read()
        at = image.find(b'name = "demo"')
        if at < 0:
            failures.append("the plan's text is not in the file as written")
        else:
            flip(text, at + len('name = "d'), 0x01)  # "demo" -> "eemo"
            refused("export of a damaged plan text",
                    run(impactid, "export", text, "--csv", os.path.join(tmp, "csv2")),
                    text, "impactid_checksum", "data corrupted")

        # merge: a shard with one flipped value.
        shards = [os.path.join(tmp, f"s{k}.h5") for k in range(2)]
        made = [run(impactid, "run", plan, "--shard", f"{k}/2", "--output", shard)
                for k, shard in enumerate(shards)]
        for k, done in enumerate(made):
            if done.returncode != 0:
                failures.append(f"shard {k}/2: exit {done.returncode}:\n{done.stderr[-2000:]}")
        if all(done.returncode == 0 for done in made):
            flip(shards[1], data_offset(shards[1], "eps_p", 1) + 7, 0x01)  # shard 1 holds point 1
            merged = run(impactid, "merge", *shards, "--output", os.path.join(tmp, "m.h5"))
            refused("merge", merged, shards[1], "eps_p", "data corrupted")
            if os.path.exists(os.path.join(tmp, "m.h5")):
                failures.append("merge wrote a file from a corrupted shard")

        # A damaged global heap, where HDF5 1.10.8 trusts the lengths it finds: the first
        # variable-length string's length made 2^40 bytes makes HDF5 copy past its buffer
        # (SIGSEGV) before any checksum can be compared. Every reader refuses the file before
        # HDF5 reads it (study/formats/first_read.cpp walks the heap's collections first).
        heap = os.path.join(tmp, "heap.h5")
        shutil.copy(good, heap)
        damage_global_heap(heap)
        before = open(heap, "rb").read()
        words = (heap, "damaged: its global heap collection at byte", "past its end")
        refused("export of a damaged heap",
                run(impactid, "export", heap, "--csv", os.path.join(tmp, "csv4")), *words)
        refused("run --resume of a damaged heap",
                run(impactid, "run", plan, "--output", heap, "--resume"), *words)
        if open(heap, "rb").read() != before:
            failures.append("run --resume changed the file with a damaged heap")
        refused("merge of a damaged heap",
                run(impactid, "merge", heap, "--output", os.path.join(tmp, "m2.h5")), *words)
        refused("plot of a damaged heap",
                run(impactid, "plot", heap, "--out", os.path.join(tmp, "figures2")), *words)

        # A file without checksums (as earlier versions wrote them): read, with a note.
        old = os.path.join(tmp, "old.h5")
        shutil.copy(good, old)
        with h5py.File(old, "r+") as f:
            if "impactid_checksum" in f.attrs:
                del f.attrs["impactid_checksum"]
        exported = run(impactid, "export", old, "--csv", os.path.join(tmp, "csv3"))
        if exported.returncode != 0 or "no checksums" not in exported.stderr:
            failures.append(f"a file without checksums: exit {exported.returncode}, no note:\n"
                            f"{exported.stderr[-2000:]}")
    for f in failures:
        print(f)
    print(f"corrupted_results_test: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
