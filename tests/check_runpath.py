#!/usr/bin/python3
"""Fails on an ELF file whose RPATH or RUNPATH has an empty or relative entry.

The dynamic loader reads an empty entry ("a:" or ":a") and a relative one
("lib", ".") against the working directory, so a binary carrying one loads
libraries from wherever it is run. $ORIGIN entries are relative to the binary
itself and allowed.

  check_runpath.py DIR [DIR...]   every ELF file under each DIR (readelf -d)
Exit 0: all clean (prints how many files were read); 1: one line per bad entry.
"""
import os
import re
import subprocess
import sys

ENTRY = re.compile(r"\((RPATH|RUNPATH)\)\s+Library r(?:un)?path: \[(.*)\]")


def elf_files(root):
    for folder, _, names in os.walk(root):
        for name in names:
            path = os.path.join(folder, name)
            if os.path.islink(path) or not os.path.isfile(path):
                continue
            try:
                with open(path, "rb") as f:
                    if f.read(4) == b"\x7fELF":
                        yield path
            except OSError:
                continue


def bad_entries(path):
    out = subprocess.run(["readelf", "-d", "-W", path], capture_output=True, text=True, check=False).stdout
    for match in ENTRY.finditer(out):
        kind, value = match.groups()
        for entry in value.split(":"):
            if entry == "":
                yield f"{path}: {kind} [{value}] has an empty entry (the working directory)"
            elif not entry.startswith("/") and not entry.startswith("$ORIGIN") and not entry.startswith("${ORIGIN}"):
                yield f"{path}: {kind} [{value}] has a relative entry '{entry}'"


def main(roots):
    if not roots:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    checked, problems = 0, []
    for root in roots:
        if not os.path.isdir(root):
            print(f"error: {root}: not a directory", file=sys.stderr)
            return 2
        for path in elf_files(root):
            checked += 1
            problems.extend(bad_entries(path))
    for p in problems:
        print(p)
    print(f"{checked} ELF files read, {len(problems)} bad RPATH/RUNPATH entries")
    return 1 if problems or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
