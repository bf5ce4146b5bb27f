#!/usr/bin/env python3
"""Deck, STL and structural model fuzz test of `quarry check` (issue 19).

Mutates the example decks, STL files and the shell models of two structure decks (bulk data and
a Gmsh mesh) a few hundred times with a fixed seed — values replaced by extremes (0, -1, 1e308,
1e-320, nan, huge integers, text), lines deleted, duplicated, swapped or truncated, bytes
flipped, binary STL counts and lengths changed, ASCII STL records damaged, model fields and
card names changed — and runs `quarry check` on each. Every mutant must exit 0 (accepted) or 2 (refused with a message),
within the time limit and under the memory limit; nothing else (a crash, 3, 4, a hang, a blow-up)
is allowed. A failing mutant is written to the work folder with its output so it can be replayed.

With --runs N it fuzzes runs instead: N deck mutants of the small examples (the fluid ones, the
periodic chute, the drum, a structure on a plate, ...); each that `check` accepts is run for a few
milliseconds of simulated time on two threads and must exit 0, 2 (refused) or 3 (the physics
stopped it, with a message), never 4 (an internal error), a signal or a hang. A fluid deck without
an outlet, inlets of 1e308 m/s and a viscosity of 9.2e18 Pa·s were found this way (exit 4 from
the fluid solver; now refused by `check`, the first two, or stopped with exit 3).

usage: fuzz_check.py QUARRY SOURCE_DIR WORK_DIR [--mutants N] [--max-mb MB] [--max-seconds S]
                     [--runs N] [--run-time S]
"""
import argparse
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import time

EXTREMES = ["0", "-1", "1e308", "-1e308", "1e-320", "nan", ".nan", ".inf", "-.inf", "9223372036854775807",
            "-9223372036854775808", "2000000000", "1e15", "0.0", "-0.0", "\"7\"", "!!str 7", "[]", "{}", "~",
            "x", "1e3000", "0x10", "1_000"]


def run_check_measured(quarry, deck, max_seconds, command=("check",)):
    """Runs `quarry check deck` (or `quarry COMMAND... deck`); returns (exit code, "timeout" or
    "signal N"; seconds; the child's own peak resident memory in MB, from wait4's ru_maxrss in KB;
    its output)."""
    start = time.monotonic()
    out_path = deck + ".out"
    with open(out_path, "wb") as out:
        pid = os.fork()
        if pid == 0:
            os.setsid()
            os.dup2(out.fileno(), 1)
            os.dup2(out.fileno(), 2)
            try:
                os.execv(quarry, [quarry, command[0], deck, *command[1:]])
            finally:
                os._exit(127)
    timed_out = False
    while True:
        finished, status, usage = os.wait4(pid, os.WNOHANG)
        if finished:
            break
        if time.monotonic() - start > max_seconds:
            timed_out = True
            os.killpg(pid, signal.SIGKILL)
            finished, status, usage = os.wait4(pid, 0)
            break
        time.sleep(0.002)
    seconds = time.monotonic() - start
    with open(out_path, "rb") as f:
        output = f.read().decode(errors="replace")
    os.remove(out_path)
    peak_mb = usage.ru_maxrss / 1024.0
    if timed_out:
        return "timeout", seconds, peak_mb, output
    if os.WIFSIGNALED(status):
        return f"signal {os.WTERMSIG(status)}", seconds, peak_mb, output
    return os.WEXITSTATUS(status), seconds, peak_mb, output


def mutate_deck(text, rng):
    lines = text.split("\n")
    kind = rng.randrange(7)
    if kind <= 2:  # a number replaced by an extreme value (the most common hostile edit)
        spots = [(i, m) for i, line in enumerate(lines) for m in re.finditer(r"-?\d+(\.\d+)?(e-?\d+)?", line)]
        if spots:
            i, m = rng.choice(spots)
            lines[i] = lines[i][:m.start()] + rng.choice(EXTREMES) + lines[i][m.end():]
    elif kind == 3 and len(lines) > 1:  # a line deleted
        del lines[rng.randrange(len(lines))]
    elif kind == 4:  # a line duplicated
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif kind == 5:  # the text cut anywhere
        joined = "\n".join(lines)
        return joined[:rng.randrange(len(joined) + 1)]
    else:  # a few characters replaced by punctuation YAML cares about, or by bytes
        chars = list("\n".join(lines))
        for _ in range(rng.randint(1, 4)):
            if chars:
                chars[rng.randrange(len(chars))] = rng.choice([":", "-", "[", "]", "{", "}", "#", "'", "\"", "\t",
                                                               "&", "*", "!", "|", ">", "\x00", "\xff", "é"])
        return "".join(chars)
    return "\n".join(lines)


def mutate_binary_stl(data, rng):
    data = bytearray(data)
    kind = rng.randrange(5)
    if kind == 0:  # the facet count in the header
        count = rng.choice([0, 1, 2**31, 2**32 - 1, len(data) // 50 + 1, rng.randrange(2**32)])
        data[80:84] = struct.pack("<I", count)
    elif kind == 1:  # truncated
        del data[rng.randrange(len(data)):]
    elif kind == 2:  # coordinates set to extremes
        for _ in range(rng.randint(1, 6)):
            facet = rng.randrange(max(1, (len(data) - 84) // 50))
            offset = 84 + facet * 50 + 12 + 4 * rng.randrange(9)
            value = rng.choice([float("nan"), float("inf"), -float("inf"), 1e30, -1e30, 1e-300, 0.0])
            data[offset:offset + 4] = struct.pack("<f", value)
    elif kind == 3:  # random bytes flipped
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
    else:  # the header made to look like text ("solid")
        data[0:5] = b"solid"
    return bytes(data)


def mutate_ascii_stl(text, rng):
    lines = text.split("\n")
    kind = rng.randrange(4)
    if kind == 0 and len(lines) > 2:
        del lines[rng.randrange(len(lines))]
    elif kind == 1:
        i = rng.randrange(len(lines))
        lines[i] = re.sub(r"-?\d+(\.\d+)?(e[-+]?\d+)?", lambda m: rng.choice(["nan", "1e30", "x", "inf", ""]),
                          lines[i], count=1)
    elif kind == 2:
        return "\n".join(lines)[:rng.randrange(len(text) + 1)]
    else:
        i = rng.randrange(len(lines))
        lines.insert(i, rng.choice(["endsolid", "facet normal 0 0 1", "vertex 1 2", "outer loop", "solid x"]))
    return "\n".join(lines)


MODEL_VALUES = ["0", "-1", "1e308", "-1e308", "nan", "inf", "9223372036854775807", "2147483647", "-2147483648",
                "4294967296", "1.e+", "+", "*", "", "x", "THRU", "ALL", "\"", "3 3", "1e3000", "-0."]


def mutate_model(text, rng):
    """A bulk-data or Gmsh model with one to three edits: a field or token replaced, a line deleted,
    duplicated, swapped or cut, a character replaced, a continuation mark or a large-field star."""
    lines = text.split("\n")
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(lines))
        line = lines[i]
        kind = rng.randrange(8)
        if kind <= 1 and line:  # a field (free, fixed 8-column or blank-separated) replaced
            if "," in line:
                fields = line.split(",")
                fields[rng.randrange(len(fields))] = rng.choice(MODEL_VALUES)
                lines[i] = ",".join(fields)
            elif kind == 0:
                k = rng.randrange(max(1, len(line) // 8))
                lines[i] = line[:8 * k] + rng.choice(MODEL_VALUES)[:8].ljust(8) + line[8 * k + 8:]
            else:
                tokens = re.split(r"(\s+)", line)
                tokens[rng.randrange(len(tokens))] = rng.choice(MODEL_VALUES)
                lines[i] = "".join(tokens)
        elif kind == 2 and len(lines) > 1:
            del lines[i]
        elif kind == 3:
            lines.insert(i, line)
        elif kind == 4:
            lines[i] = line[:rng.randrange(len(line) + 1)]
        elif kind == 5:
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif kind == 6 and line:
            k = rng.randrange(len(line))
            lines[i] = line[:k] + rng.choice(["+", "*", ",", "\t", "$", "\x00", "\xff", "é", " "]) + line[k + 1:]
        else:  # a card or section name changed
            lines[i] = rng.choice(["+", "*", "CQUAD4", "CTRIA3", "GRID*", "$Nodes", "$EndElements", "ENDDATA"]) + \
                line[len(line.split(",")[0].split(" ")[0]):]
    return "\n".join(lines)


def ascii_stl_from_binary(data):
    """An ASCII rendering of a binary STL (so that the text reader is fuzzed too)."""
    count = struct.unpack("<I", data[80:84])[0]
    out = ["solid fuzz"]
    for f in range(min(count, 400)):
        values = struct.unpack("<12f", data[84 + 50 * f:84 + 50 * f + 48])
        out.append(f"facet normal {values[0]:g} {values[1]:g} {values[2]:g}")
        out.append("outer loop")
        for v in range(3):
            x, y, z = values[3 + 3 * v:6 + 3 * v]
            out.append(f"vertex {x:.9g} {y:.9g} {z:.9g}")
        out.append("endloop")
        out.append("endfacet")
    out.append("endsolid fuzz")
    return "\n".join(out) + "\n"


def problems_of(code, output, peak_mb, allowed, max_mb, name="exit"):
    """What is wrong with one outcome: an exit code not allowed, a refusal without a message, too
    much memory."""
    problems = [f"{name} {code}"] if code not in allowed else []
    if code in allowed and code != 0 and "error" not in output:
        problems.append(f"exit {code} without an error message")
    if peak_mb > max_mb:
        problems.append(f"{peak_mb:.0f} MB > {max_mb:.0f} MB")
    return problems


def settle(folder, what, problems, output, failures):
    """Keeps a failing mutant's folder with its output (to replay it); removes a passing one."""
    if problems:
        failures.append(f"{folder} ({what}): {', '.join(problems)}\n{output[-2000:]}")
        open(os.path.join(folder, "output.txt"), "w").write(output)
    else:
        shutil.rmtree(folder)


def report(summary, failures):
    print(summary)
    for f in failures:
        print("FAILED:", f)
    return 1 if failures else 0


# Decks small enough to run: (deck, files beside it that it reads).
RUN_DECKS = [("examples/packed_bed/packed_bed.yaml", []), ("examples/fluidised_bed/fluidised_bed.yaml", []),
             ("examples/periodic_chute/periodic_chute.yaml", []), ("examples/rotating_drum/rotating_drum.yaml", []),
             ("examples/bouncing_sphere/bouncing_sphere.yaml", []), ("examples/hopper/hopper.yaml", ["hopper.stl"]),
             ("tests/decks/minimal.yaml", []), ("tests/fsi/plate_bed.yaml", ["plate_8x8.bdf"])]


def fuzz_runs(args, rng):
    """The run stage (--runs): deck mutants that `check` accepts, run briefly; 0, 2 or 3 only."""
    outcomes = {}
    failures = []
    ran = 0
    for n in range(args.runs):
        deck_name, beside = rng.choice(RUN_DECKS)
        source = os.path.join(args.source_dir, deck_name)
        text = open(source).read()
        for _ in range(rng.randint(1, 2)):
            text = mutate_deck(text, rng)
        folder = os.path.join(args.work_dir, f"run{n:04d}")
        os.makedirs(folder)
        for name in beside:
            shutil.copy(os.path.join(os.path.dirname(source), name), folder)
        deck_path = os.path.join(folder, "deck.yaml")
        open(deck_path, "w", encoding="utf-8", errors="surrogateescape").write(text)
        code, _, peak_mb, output = run_check_measured(args.quarry, deck_path, args.max_seconds)
        problems = problems_of(code, output, peak_mb, (0, 2), args.max_mb, "check exit")
        if code == 0:
            ran += 1
            command = ("run", "--threads", "2", "--end-time", str(args.run_time), "--quiet",
                       "--output-dir", os.path.join(folder, "out"))
            code, _, peak_mb, output = run_check_measured(args.quarry, deck_path, args.max_seconds, command)
            outcomes[code] = outcomes.get(code, 0) + 1
            problems += problems_of(code, output, peak_mb, (0, 2, 3), args.max_mb, "run exit")
        settle(folder, f"mutant of {deck_name}", problems, output, failures)
    return report(f"{args.runs} deck mutants (seed {args.seed}), {ran} accepted and run for {args.run_time} s: "
                  f"run outcomes {outcomes}", failures)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("quarry")
    parser.add_argument("source_dir")
    parser.add_argument("work_dir")
    parser.add_argument("--mutants", type=int, default=300)
    parser.add_argument("--max-mb", type=float, default=400.0)
    parser.add_argument("--max-seconds", type=float, default=10.0)
    parser.add_argument("--seed", type=int, default=20261202)
    parser.add_argument("--runs", type=int, default=0)
    parser.add_argument("--run-time", type=float, default=0.002)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    shutil.rmtree(args.work_dir, ignore_errors=True)
    os.makedirs(args.work_dir)
    if args.runs > 0:
        return fuzz_runs(args, rng)
    examples = os.path.join(args.source_dir, "examples")
    decks = {name: open(os.path.join(examples, name)).read() for name in
             ["bouncing_sphere/bouncing_sphere.yaml", "rotating_drum/rotating_drum.yaml", "hopper/hopper.yaml",
              "truck_bed/truck_bed.yaml"]}
    decks["minimal.yaml"] = open(os.path.join(args.source_dir, "tests", "decks", "minimal.yaml")).read()
    hopper_stl = open(os.path.join(examples, "hopper", "hopper.stl"), "rb").read()
    hopper_deck = decks["hopper/hopper.yaml"]
    # Structure decks whose model lies beside them: bulk data (plate_8x8.bdf) and a Gmsh mesh.
    fsi = os.path.join(args.source_dir, "tests", "fsi")
    models = [
        (open(os.path.join(fsi, "plate_bed.yaml")).read(), "plate_8x8.bdf",
         open(os.path.join(fsi, "plate_8x8.bdf")).read()),
        (open(os.path.join(fsi, "plate_mesh.yaml")).read().replace("../models/plate.msh", "plate.msh"), "plate.msh",
         open(os.path.join(args.source_dir, "tests", "models", "plate.msh")).read()),
    ]

    outcomes = {}
    failures = []
    slowest = (0.0, "")
    largest = (0.0, "")
    for n in range(args.mutants):
        folder = os.path.join(args.work_dir, f"{n:04d}")
        os.makedirs(folder)
        deck_path = os.path.join(folder, "deck.yaml")
        what = ""
        if n % 3 == 2:  # an STL mutant under the (unchanged) hopper deck
            if rng.random() < 0.5:
                open(os.path.join(folder, "hopper.stl"), "wb").write(mutate_binary_stl(hopper_stl, rng))
                what = "binary STL mutant of hopper.stl"
            else:
                text = mutate_ascii_stl(ascii_stl_from_binary(hopper_stl), rng)
                open(os.path.join(folder, "hopper.stl"), "w", encoding="utf-8", errors="surrogateescape").write(text)
                what = "ASCII STL mutant of hopper.stl"
            open(deck_path, "w").write(hopper_deck)
        elif n % 3 == 1:  # a structural model mutant under its (unchanged) deck
            deck, model_name, model = models[(n // 3) % 2]
            open(os.path.join(folder, model_name), "w", encoding="utf-8", errors="surrogateescape").write(
                mutate_model(model, rng))
            open(deck_path, "w").write(deck)
            what = f"model mutant of {model_name}"
        else:
            name = rng.choice(sorted(decks))
            open(deck_path, "w", encoding="utf-8", errors="surrogateescape").write(mutate_deck(decks[name], rng))
            what = f"deck mutant of {name}"
            for stl in ("hopper/hopper.stl", "truck_bed/truck_bed.stl"):  # decks name their STL beside them
                shutil.copy(os.path.join(examples, stl), folder)
        code, seconds, peak_mb, output = run_check_measured(args.quarry, deck_path, args.max_seconds)
        outcomes[code] = outcomes.get(code, 0) + 1
        slowest = max(slowest, (seconds, folder))
        largest = max(largest, (peak_mb, folder))
        settle(folder, what, problems_of(code, output, peak_mb, (0, 2), args.max_mb), output, failures)
    return report(f"{args.mutants} mutants (seed {args.seed}): outcomes {outcomes}; slowest {slowest[0]:.2f} s, "
                  f"largest {largest[0]:.0f} MB", failures)


if __name__ == "__main__":
    sys.exit(main())
