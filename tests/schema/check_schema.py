#!/usr/bin/env python3
"""Checks docs/scene.schema.json against glint's scene loader.

1. The schema is a valid JSON Schema draft 2020-12.
2. Every scenes/**/*.json validates against it.
3. Every tests/schema/invalid/*.json is rejected by the schema AND by
   `glint render` (non-zero exit, an `error: ` line on stderr, no crash), and
   the two reject it at the same place: one of the schema's error locations
   and the JSON path in glint's message are equal or one contains the other.
4. Every tests/schema/valid/*.json passes the schema and renders with glint.

Usage: check_schema.py --glint PATH/TO/glint [--root PROJECT_DIR]
Without --glint only the schema side is checked. Needs python3-jsonschema;
exits 77 (CTest: skipped) when it is missing.
"""

import argparse
import concurrent.futures
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

try:
    import jsonschema
except ImportError:
    print("schema: skipped, the Python module jsonschema is missing "
          "(Debian: apt-get install python3-jsonschema)")
    sys.exit(77)

HERE = Path(__file__).resolve().parent
SKIP_BINARY_MARK = "mesh objects are not supported"  # this build's known limit


def load_json(path):
    # A leading byte-order mark is allowed in scene files.
    with open(path, encoding="utf-8-sig") as f:
        return json.load(f)


def format_path(parts):
    """['objects', 0, 'radius'] -> 'objects[0].radius', as glint writes it."""
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += ("." if out else "") + str(p)
    return out


def all_errors(validator, instance):
    """Every error, descending into oneOf/anyOf/if-then sub-errors."""
    stack = list(validator.iter_errors(instance))
    while stack:
        e = stack.pop()
        yield e
        stack.extend(e.context or [])


def related(a, b):
    """Whether JSON path a equals b or one is a prefix of the other."""
    def split(p):
        return re.findall(r"[^.\[\]]+|\[\d+\]", p)
    sa, sb = split(a), split(b)
    n = min(len(sa), len(sb))
    return sa[:n] == sb[:n]


def run_glint(glint, scene, out_dir):
    out = Path(out_dir) / (scene.stem + ".pfm")
    try:
        proc = subprocess.run([glint, "render", str(scene), "-o", str(out), "--quiet"],
                              capture_output=True, text=True, errors="replace", timeout=60)
    except subprocess.TimeoutExpired:
        return None, "timed out after 60 s"
    return proc.returncode, proc.stderr


def loader_path(stderr, scene):
    """The JSON path in `error: FILE:LINE:COL: PATH: what`, or None."""
    for line in stderr.splitlines():
        if not line.startswith("error: "):
            continue
        rest = line[len("error: "):]
        prefix = f"{scene}:"
        if rest.startswith(prefix):
            rest = rest[len(prefix):]
        m = re.match(r"\d+:\d+: ([A-Za-z_$][\w$]*(?:\[\d+\]|\.[\w$-]+)*): ", rest)
        if m:
            return "" if m.group(1) == "scene" else m.group(1)
        return None
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--glint", help="path to the glint binary (omit to check the schema side only)")
    ap.add_argument("--root", default=str(HERE.parent.parent), help="project root (default: from this script)")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every check")
    args = ap.parse_args()
    root = Path(args.root).resolve()

    passed = failed = skipped = 0
    failures = []

    def ok(what):
        nonlocal passed
        passed += 1
        if args.verbose:
            print(f"ok    {what}")

    def bad(what):
        nonlocal failed
        failed += 1
        failures.append(what)
        print(f"FAIL  {what}")

    # 1. The schema itself.
    schema_path = root / "docs" / "scene.schema.json"
    schema = load_json(schema_path)
    try:
        jsonschema.Draft202012Validator.check_schema(schema)
        ok(f"{schema_path.relative_to(root)} is a valid draft 2020-12 schema")
    except jsonschema.exceptions.SchemaError as e:
        bad(f"{schema_path.relative_to(root)} is not a valid draft 2020-12 schema: {e.message}")
        print(f"schema: {passed} passed, {failed} failed")
        return 1
    if schema.get("$schema") != "https://json-schema.org/draft/2020-12/schema":
        bad("the schema does not declare draft 2020-12 in $schema")
    validator = jsonschema.Draft202012Validator(schema)

    def schema_errors(doc):
        return sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))

    # 2. Every scene in scenes/.
    scenes = sorted((root / "scenes").rglob("*.json"))
    if not scenes:
        bad("no scenes found under scenes/")
    for scene in scenes:
        rel = scene.relative_to(root)
        try:
            errs = schema_errors(load_json(scene))
        except ValueError as e:
            bad(f"{rel}: not JSON: {e}")
            continue
        if errs:
            for e in errs[:5]:
                bad(f"{rel}: schema rejects it: {format_path(e.absolute_path) or '(root)'}: {e.message}")
        else:
            ok(f"{rel}: schema accepts it")

    invalid = sorted((HERE / "invalid").glob("*.json"))
    valid = sorted((HERE / "valid").glob("*.json"))
    if len(invalid) < 30:
        bad(f"only {len(invalid)} invalid fixtures in tests/schema/invalid (want 30 or more)")

    # 3./4. Fixtures: the schema side, then the binary side (in parallel).
    schema_verdicts = {}
    for fixture in invalid + valid:
        rel = fixture.relative_to(root) if fixture.is_relative_to(root) else fixture
        try:
            doc = load_json(fixture)
        except ValueError as e:
            bad(f"{rel}: not JSON ({e}); fixtures must be JSON broken only in what the schema can see")
            continue
        errs = list(all_errors(validator, doc))
        schema_verdicts[fixture] = errs
        top = [e for e in errs if e.parent is None]
        if fixture in invalid:
            if top:
                best = jsonschema.exceptions.best_match(top)
                ok(f"{rel}: schema rejects it ({format_path(best.absolute_path) or '(root)'}: {best.message[:80]})")
            else:
                bad(f"{rel}: schema accepts an invalid scene")
        else:
            if top:
                for e in top[:5]:
                    bad(f"{rel}: schema rejects a valid scene: {format_path(e.absolute_path) or '(root)'}: {e.message}")
            else:
                ok(f"{rel}: schema accepts it")

    if not args.glint:
        print("note: --glint not given, the loader side was not checked")
    else:
        glint = str(Path(args.glint).resolve())
        if not os.access(glint, os.X_OK):
            print(f"schema: cannot run the glint binary {glint}")
            return 1
        with tempfile.TemporaryDirectory(prefix="glint-schema-") as out_dir:
            with concurrent.futures.ThreadPoolExecutor(max_workers=min(16, (os.cpu_count() or 2) * 2)) as pool:
                results = dict(zip(invalid + valid,
                                   pool.map(lambda f: run_glint(glint, f, out_dir), invalid + valid)))
        for fixture, (rc, stderr) in results.items():
            rel = fixture.relative_to(root) if fixture.is_relative_to(root) else fixture
            first = next((l for l in stderr.splitlines() if l.startswith("error: ")), None) if rc is not None else None
            if fixture in invalid:
                if rc is None:
                    bad(f"{rel}: glint {stderr}")
                elif rc < 0:
                    bad(f"{rel}: glint crashed (signal {-rc})")
                elif rc == 0:
                    bad(f"{rel}: glint accepts this invalid scene (exit 0)")
                elif first is None:
                    bad(f"{rel}: glint exits {rc} without an 'error: ' line (stderr: {stderr.strip()[:200]!r})")
                else:
                    where = loader_path(stderr, fixture)
                    spots = {format_path(e.absolute_path) for e in schema_verdicts.get(fixture, [])}
                    if (SKIP_BINARY_MARK in first or where is None or not spots
                            or any(related(where, s) for s in spots)):
                        ok(f"{rel}: glint rejects it: {first[len('error: '):][:100]}")
                    else:
                        bad(f"{rel}: glint and the schema reject it at different places: glint at "
                            f"{where!r} ({first}), the schema at {sorted(spots)}")
            else:
                if rc == 0:
                    ok(f"{rel}: glint renders it")
                elif rc is not None and rc > 0 and first and SKIP_BINARY_MARK in first:
                    skipped += 1
                    print(f"skip  {rel}: this glint build has no mesh objects ({first})")
                else:
                    bad(f"{rel}: glint fails on a valid scene (exit {rc}): {stderr.strip()[:300]}")

    print(f"schema: {passed} passed, {failed} failed"
          + (f", {skipped} skipped" if skipped else "")
          + f" ({len(scenes)} scenes, {len(invalid)} invalid and {len(valid)} valid fixtures)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
