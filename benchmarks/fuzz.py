"""Fuzz the three parsers with N generated inputs, each under a time and a memory limit.

Run: ``.venv/bin/python benchmarks/fuzz.py N [--workers W] [--seed S]``.

Inputs are mutations of the golden corpus and examples (choreographies and world files),
random tokens and hostile numbers (0, -0, 5e-324, 1e-300, 1e308, 10**400, nan, inf, ...),
and /sync messages. Each goes to a worker process (a pool of ``--workers``, each handling many
inputs, its address space limited by ``resource.setrlimit(RLIMIT_AS)``):

* scenario: ``compile_scenario`` then ``check_plan`` (a quarter of them in a corpus world);
* world: ``parse_world``;
* sync: ``dancebots.sync.parse_message``.

A failure is a traceback (any exception but the documented ``SyncMessageError``), a
``MemoryError`` or a worker killed for memory, a hang (an input not done within
``--timeout`` s of wall clock; it is retried once alone in a fresh worker before it counts,
since the machine is shared), or a diagnostic without a real position (line >= 1, col >= 1,
within the text). Each kind of failure is shrunk to a minimal reproducer (lines, then
words removed while it still fails the same way). Prints inputs/s and the failures; exits 1
on any failure.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import multiprocessing
import multiprocessing.connection
import os
import random
import re
import sys
import time
import traceback
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

HOSTILE = ["0", "-0", "-0.0", "5e-324", "-5e-324", "1e-300", "1e-320", "1e308", "-1e308",
           "1e309", "1" + "0" * 400, "-1" + "0" * 400, "nan", "NaN", "inf", "-inf",
           "Infinity", "0x10", "1_000", "1e", ".", "-", "+", "١٢", "36000", "36001", "1000",
           "1000.0001", "-1000", "0.01", "0.009", "0.001", "0.0009", "10", "10.5", "360",
           "-360", "999999999999999999999", "1e-9", "2.5", "1.2", "90", "-90", "3"]
NAMES = ["R1", "R2", "R3", "R4", "g1", "g2", "group1", "R1,R2", "R1;R2", "R1,R2;R3,R4", ",",
         ";", "R1,,R2", "R9", "é", "_", "a.b-c", "1R", "row", "newVL"]
KEYWORDS = ["robots", "groups", "start", "row", "column", "triangle", "square", "move",
            "circle", "newVL", "newvl", "#", "# comment", "Move", "mvoe"]
JUNK = ["\x00", "\t", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029",
        "\r", "\r\n", "\ufeff", "\udc80", "ß", "🤖", "\"", "'", "[", "]", "=", "{", "}"]
BREAKS = ["\r\n", "\r", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"]
SYNC_WORDS = ["test", "sync", "R1", "R2", "_a.b-c", "1R", "é", "1732.25", "1e9", "0",
              *HOSTILE, "", "test\x00", "sync\u2028R1"]
_NUMBER = re.compile(r"(?<![A-Za-z0-9_.])[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
                     r"(?![A-Za-z0-9_.])")  # numbers, not the digits of names like R1


@dataclass(frozen=True, slots=True)
class Item:
    """One input: ``kind`` scenario, world or sync; ``text``; for a scenario, optionally the
    text of a world to check it in."""

    kind: str
    text: str
    world: str | None = None


@dataclass(frozen=True, slots=True)
class Outcome:
    """What a worker found: ``status`` ok, traceback, memory, position or hang; ``signature``
    identifies the kind of failure (for grouping and shrinking); ``detail`` shows it."""

    status: str
    signature: str = ""
    detail: str = ""
    seconds: float = 0.0


# --- generation ------------------------------------------------------------------------------

def corpus() -> tuple[list[str], list[str]]:
    """The choreographies and world files that mutations start from."""
    dances = sorted({*ROOT.glob("examples/*.dance"), *ROOT.glob("tests/data/scenarios/*/*.dance"),
                     *ROOT.glob("src/dancebots/data/*.dance")})
    worlds = sorted({*ROOT.glob("examples/worlds/*.toml"), *ROOT.glob("tests/data/worlds/*.toml"),
                     *ROOT.glob("src/dancebots/data/*.toml")})
    read = [p.read_bytes().decode("utf-8", errors="replace") for p in dances]
    return read, [p.read_text(encoding="utf-8") for p in worlds]


def _lines(text: str) -> list[str]:
    return text.split("\n")


def _gentle(rng: random.Random) -> str:
    """A number a show might well hold: a length, an angle or a speed."""
    return rng.choice([f"{rng.uniform(0, 5):.3g}", str(rng.randint(-360, 360)),
                       f"{rng.uniform(0.001, 2):.3g}", str(rng.randint(0, 1000)),
                       f"{rng.uniform(-1000, 1000):.4g}"])


def _scaled(rng: random.Random, number: str) -> str:
    """``number`` times a factor from 0.5 to 2 (or unchanged), in the same style."""
    if rng.random() < 0.5:
        return number
    value = float(number) * rng.uniform(0.5, 2.0)
    return f"{value:.3g}" if "." in number or "e" in number.lower() else str(round(value))


def _mutate_numbers(rng: random.Random, text: str) -> str:
    spans = [m.span() for m in _NUMBER.finditer(text)]
    if not spans:
        return text
    a, b = rng.choice(spans)
    number = rng.choice(HOSTILE) if rng.random() < 0.4 else _gentle(rng)
    return text[:a] + number + text[b:]


def _mutate_line(rng: random.Random, text: str, vocabulary: list[str]) -> str:
    lines = _lines(text)
    k = rng.randrange(len(lines))
    op = rng.randrange(6)
    if op == 0:
        del lines[k]
    elif op == 1:
        lines[k:k] = [lines[k]] * rng.randint(1, 40)
    elif op == 2:
        lines.insert(k, " ".join(rng.choice(vocabulary) for _ in range(rng.randint(0, 6))))
    elif op == 3:
        words = lines[k].split(" ")
        words[rng.randrange(len(words))] = rng.choice(vocabulary)
        lines[k] = " ".join(words)
    elif op == 4:
        lines = lines * rng.randint(2, 8)
    else:
        lines[k] = lines[k] + rng.choice(BREAKS) + rng.choice(lines)
    return "\n".join(lines)


def _mutate_chars(rng: random.Random, text: str) -> str:
    at = rng.randrange(len(text) + 1)
    op = rng.randrange(3)
    if op == 0:
        return text[:at] + rng.choice(JUNK) + text[at:]
    if op == 1:
        return text[:at]
    return text[:at] + text[at + rng.randint(1, 5):]


def _crowd(rng: random.Random) -> str:
    """Many robots in one row, some split off and moved: the robot-pair checks' worst case."""
    count = rng.choice([50, 200, 999, 1000, 1001, 1200])
    names = [f"R{i}" for i in range(count)]
    half = names[: count // 2]
    text = ("robots " + " ".join(names) + "\ngroups\nL " + " ".join(half) + "\nstart\nrow "
            + ",".join(names) + f" 0 {rng.choice(['1.2', '0', '0.5'])}\nmove 2 0\n")
    if rng.random() < 0.5:
        text += "row " + ",".join(half) + " 0 1.2\nnewVL\nmove 3 30 L\n"
    return text


def generate(rng: random.Random, dances: list[str], worlds: list[str]) -> Item:
    """One input, drawn from the seeded ``rng``."""
    kind = rng.choices(["scenario", "world", "sync"], weights=[4, 3, 3])[0]
    if kind == "sync":
        if rng.random() < 0.2:
            return Item("sync", "".join(rng.choice(JUNK + SYNC_WORDS)
                                        for _ in range(rng.randint(0, 8))))
        words = [rng.choice(SYNC_WORDS) for _ in range(rng.randint(0, 4))]
        if rng.random() < 0.5:
            words = [rng.choice(["test", "sync"]), *words]
        return Item("sync", rng.choice([" ", "  ", "\t", "\n"]).join(words))
    if kind == "scenario" and rng.random() < 0.005:
        return Item("scenario", _crowd(rng))
    vocabulary = KEYWORDS + NAMES + HOSTILE if kind == "scenario" else (
        ["[room]", "[[robots]]", "[[obstacles]]", "[[spectators]]", "size =", "x =", "y =",
         "speed =", "path =", "polygon =", "name =", '"R1"', "true", *HOSTILE])
    text = rng.choice(dances if kind == "scenario" else worlds)
    if kind == "scenario" and rng.random() < 0.4:  # a plausible show: every number rescaled
        return Item(kind, _NUMBER.sub(lambda m: _scaled(rng, m.group()), text),
                    rng.choice(worlds) if rng.random() < 0.25 else None)
    for _ in range(rng.choice([1, 1, 1, 2, 2, 3, 4])):
        r = rng.random()
        if r < 0.6 if kind == "scenario" else r < 0.45:
            text = _mutate_numbers(rng, text)
        elif r < 0.85:
            text = _mutate_line(rng, text, vocabulary)
        else:
            text = _mutate_chars(rng, text)
    world = rng.choice(worlds) if kind == "scenario" and rng.random() < 0.25 else None
    return Item(kind, text, world)


# --- the worker ------------------------------------------------------------------------------

def _positions(diagnostics: object, text: str) -> str | None:
    """What is wrong with the diagnostics' positions in ``text``, or None."""
    from dancebots.diagnostics import source_lines

    last = max(1, len(source_lines(text)))
    for d in diagnostics:  # type: ignore[attr-defined]
        if not (1 <= d.line <= last and d.col >= 1):
            return f"diagnostic at {d.line}:{d.col} of a {last}-line text: {d.headline()}"
    return None


def run_one(item: Item) -> Outcome:
    """Run one input in this process; every failure is an Outcome, never an exception."""
    from dancebots.check import check_plan
    from dancebots.plan.compile import compile_scenario
    from dancebots.sync import parse_message
    from dancebots.sync.messages import SyncMessageError
    from dancebots.world import parse_world

    start = time.process_time()
    try:
        problem: str | None = None
        if item.kind == "selftest":  # --self-test: the harness must see each of these
            if item.text == "hang":
                while True:
                    pass
            if item.text == "memory":
                problem = str(len(bytearray(4 << 30)))
            if item.text == "traceback":
                raise RuntimeError("a planted traceback")
        elif item.kind == "sync":
            with contextlib.suppress(SyncMessageError):  # the documented refusal
                parse_message(item.text)
        elif item.kind == "world":
            world, diagnostics = parse_world(item.text, "fuzz.toml")
            problem = _positions(diagnostics, item.text)
        else:
            _, plan, diagnostics = compile_scenario(item.text, "fuzz.dance")
            problem = _positions(diagnostics, item.text)
            if plan is not None and problem is None:
                world = None
                if item.world is not None:
                    world, _ = parse_world(item.world, "fuzz.toml")
                report = check_plan(plan, world)
                own = [d for d in report.diagnostics if d.path == "fuzz.dance"]
                other = [d for d in report.diagnostics if d.path != "fuzz.dance"]
                problem = _positions(own, item.text) or (
                    _positions(other, item.world) if item.world is not None else None)
        if problem is not None:
            return Outcome("position", "position " + re.sub(r"[\d.]+", "N", problem[:60]),
                           problem, time.process_time() - start)
        return Outcome("ok", seconds=time.process_time() - start)
    except MemoryError:
        return Outcome("memory", "MemoryError", traceback.format_exc(limit=-3),
                       time.process_time() - start)
    except Exception as exc:  # a fuzzer reports every exception
        frames = traceback.extract_tb(exc.__traceback__)
        where = f"{Path(frames[-1].filename).name}:{frames[-1].lineno}" if frames else "?"
        return Outcome("traceback", f"{type(exc).__name__} at {where}",
                       traceback.format_exc(limit=-4), time.process_time() - start)


def _worker(conn: multiprocessing.connection.Connection, memory: int) -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    while True:
        try:
            item = conn.recv()
        except EOFError:
            return
        conn.send(run_one(item))


class Pool:
    """Worker processes that each handle many inputs; one that hangs or dies is replaced."""

    def __init__(self, workers: int, timeout: float, memory: int) -> None:
        self.timeout, self.memory = timeout, memory
        self.context = multiprocessing.get_context("fork")
        self.slots: list[tuple[multiprocessing.process.BaseProcess,
                               multiprocessing.connection.Connection]] = [
            self._spawn() for _ in range(workers)]

    def _spawn(self) -> tuple[multiprocessing.process.BaseProcess,
                              multiprocessing.connection.Connection]:
        parent, child = self.context.Pipe()
        process = self.context.Process(target=_worker, args=(child, self.memory), daemon=True)
        process.start()
        child.close()
        return process, parent

    def _replace(self, slot: int) -> None:
        process, conn = self.slots[slot]
        process.kill()
        process.join()
        conn.close()
        self.slots[slot] = self._spawn()

    def map(self, items: Iterator[Item]) -> Iterator[tuple[Item, Outcome]]:
        """Outcomes of all items, in completion order."""
        busy: dict[int, tuple[Item, float]] = {}
        pending = iter(items)
        exhausted = False
        while True:
            for slot in range(len(self.slots)):
                if slot not in busy and not exhausted:
                    item = next(pending, None)
                    if item is None:
                        exhausted = True
                        break
                    self.slots[slot][1].send(item)
                    busy[slot] = (item, time.monotonic())
            if not busy:
                return
            ready = multiprocessing.connection.wait(
                [self.slots[s][1] for s in busy], timeout=0.05)
            now = time.monotonic()
            for slot in list(busy):
                item, began = busy[slot]
                conn = self.slots[slot][1]
                if conn in ready:
                    try:
                        outcome = conn.recv()
                    except (EOFError, OSError):  # the worker died: the memory limit
                        outcome = Outcome("memory", "worker died", "the worker process died")
                        self._replace(slot)
                    del busy[slot]
                    yield item, outcome
                elif now - began > self.timeout:
                    self._replace(slot)
                    del busy[slot]
                    yield item, Outcome("hang", "hang", f"not done after {self.timeout:g} s",
                                        now - began)

    def run(self, item: Item) -> Outcome:
        return next(iter(self.map(iter([item]))))[1]

    def close(self) -> None:
        for process, conn in self.slots:
            conn.close()
            process.join(timeout=1)
            if process.is_alive():
                process.kill()


# --- shrinking -------------------------------------------------------------------------------

def shrink(item: Item, fails: Callable[[Item], bool], budget: int = 150) -> Item:
    """A smaller item that still fails: whole lines, then words, removed greedily."""
    runs = 0
    for splitter, joiner in (("\n", "\n"), (" ", " ")):
        parts = item.text.split(splitter)
        k = 0
        while k < len(parts) and runs < budget:
            candidate = Item(item.kind, joiner.join(parts[:k] + parts[k + 1:]), item.world)
            runs += 1
            if fails(candidate):
                parts = parts[:k] + parts[k + 1:]
                item = candidate
            else:
                k += 1
    return item


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("n", type=int, help="number of inputs")
    parser.add_argument("--workers", type=int, default=2, help="worker processes")
    parser.add_argument("--seed", type=int, default=0, help="seed of the generator")
    parser.add_argument("--timeout", type=float, default=2.0, help="s per input (wall)")
    parser.add_argument("--memory-mb", type=int, default=1024,
                        help="address-space limit of each worker, MiB")
    parser.add_argument("--save", type=Path, metavar="DIR",
                        help="write every failing input to DIR (one file per input)")
    parser.add_argument("--self-test", action="store_true",
                        help="first plant a hang, a memory hog and a traceback and check that "
                        "each is reported")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    for module in ("dancebots.check", "dancebots.sync", "dancebots.world"):
        importlib.import_module(module)  # loaded once, before the workers fork

    dances, worlds = corpus()
    rng = random.Random(args.seed)
    pool = Pool(args.workers, args.timeout, args.memory_mb * 1024 * 1024)
    kinds: Counter[str] = Counter()
    failures: dict[str, tuple[Item, Outcome]] = {}
    counts: Counter[str] = Counter()
    retried = 0
    slowest = (0.0, "")
    items = (generate(rng, dances, worlds) for _ in range(args.n))
    retry = Pool(1, args.timeout, args.memory_mb * 1024 * 1024)
    if args.self_test:
        planted = [Item("selftest", kind) for kind in ("hang", "memory", "traceback")]
        seen = sorted(outcome.status for _, outcome in pool.map(iter(planted)))
        print(f"self-test: planted hang, memory, traceback; reported {', '.join(seen)}")
        if seen != ["hang", "memory", "traceback"]:
            return 2
    began = time.monotonic()
    for done, (item, outcome) in enumerate(pool.map(items), start=1):
        kinds[item.kind] += 1
        if outcome.status == "hang":  # the machine is shared: a hang must hang twice
            again = retry.run(item)
            if again.status != "hang":
                retried += 1
                outcome = again
        if outcome.seconds > slowest[0] and outcome.status != "hang":
            slowest = (outcome.seconds, item.kind)
        if outcome.status != "ok":
            counts[outcome.status] += 1
            failures.setdefault(outcome.signature, (item, outcome))
            if args.save is not None:
                args.save.mkdir(parents=True, exist_ok=True)
                name = f"{done:06d}-{outcome.status}.{item.kind}"
                (args.save / name).write_text(item.text, encoding="utf-8",
                                              errors="surrogateescape")
                if item.world is not None:
                    (args.save / (name + ".world.toml")).write_text(item.world, encoding="utf-8")
        if done % 10_000 == 0:
            rate = done / (time.monotonic() - began)
            print(f"  {done} inputs, {rate:.0f}/s, {sum(counts.values())} failures",
                  file=sys.stderr, flush=True)
    elapsed = time.monotonic() - began
    pool.close()
    total = sum(kinds.values())
    print(f"fuzz: {total} inputs ({', '.join(f'{k} {v}' for k, v in sorted(kinds.items()))}) "
          f"in {elapsed:.1f} s: {total / elapsed:.1f} inputs/s with {args.workers} workers, "
          f"{args.timeout:g} s and {args.memory_mb} MiB per input")
    print(f"slowest completed input: {slowest[0]:.2f} s CPU ({slowest[1]}); inputs that "
          f"timed out once under load and then passed alone: {retried}")
    failed = sum(counts.values())
    print(f"failures: {failed} (tracebacks {counts['traceback']}, hangs {counts['hang']}, "
          f"memory {counts['memory']}, positions {counts['position']})")
    for signature, (item, outcome) in sorted(failures.items()):
        small = shrink(item, lambda c, s=signature: retry.run(c).signature == s)
        print(f"\n== {outcome.status}: {signature}\nminimal {small.kind} input: {small.text!r}"
              + (f"\nin world: {small.world!r}" if small.world else "")
              + f"\n{outcome.detail.rstrip()}")
    retry.close()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
