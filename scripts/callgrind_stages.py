#!/usr/bin/env python3
"""callgrind_stages.py -- instructions a collision, stage by stage, for our engine and for
Smallenburg's EDMD ("Single"), from callgrind: where the event-driven engine's instructions
go against the peer's (docs/benchmarks.md, "Stage by stage against the peer").

Usage:
    python3 scripts/callgrind_stages.py ours SIM_RATE N PHI
    python3 scripts/callgrind_stages.py peer SHORT_DIR LONG_DIR

ours   SIM_RATE is a `sim_rate` binary (`cargo build --release -p spheresweep-bench --example
       sim_rate`; the release profile keeps line tables, which this needs). It is run under
       callgrind for `T` = 2 and 6, and each instruction's count in the longer run less the
       shorter one is divided by the difference of their collisions, so that the set-up
       cancels. Each instruction goes to a stage by the functions inlined at it (`objdump
       --inlines`): the calendar, the shell exit and horizon, the two passes of a
       prediction, a rebuild's cell scan and list upkeep, the collision, the event loop.
peer   SHORT_DIR and LONG_DIR each hold the peer's `md`, built by `EDMD_CFLAGS="-Ofast
       -march=x86-64-v3" scripts/edmd_peer.sh EDMD N PHI MAXTIME DIR` for two simulated times
       (e.g. 10^5 and 3*10^5 collisions; the target ours is built for: valgrind cannot run
       every instruction `-march=native` may use); each is run there under callgrind, its collision count read from its last "Collisions:" line, and
       each function's own instructions are differenced the same way.

Needs valgrind and binutils' objdump. Prints one line a stage: instructions a collision.
The split of ours is as good as the compiler's line tables, which put some instructions of an
inlined function under its caller's line (the shell exit's arithmetic under the index that
loads the shell's centre, for one): a stage's figure is good to a few tens of instructions;
the total is exact.
"""
import collections
import os
import re
import subprocess
import sys
import tempfile

# A stage for each instruction, from the functions of our sources it is inlined through
# (`names`, innermost first) and the symbol it sits in (`sym`): the first rule that matches.
STAGES = [
    ("calendar", lambda names, files, sym: "queue.rs" in files),
    ("shell exit and horizon", lambda names, files, sym: any(
        n in ("shell_exit_quotient", "shell_exit_falling", "predict_shell", "horizon",
              "reaching", "value") for n in names)),
    ("rebuild: cell scan", lambda names, files, sym: any(
        n in ("within_reach", "cells_near", "around", "coords_of", "fetch_gathered_shells")
        for n in names) or any(s in sym for s in ("within_reach", "coords_of", "cells_near"))),
    ("prediction: first pass (screen)", lambda names, files, sym: "screen" in sym or any(
        n in ("screen", "screen_all") for n in names)),
    ("prediction: second pass (answer, keep)", lambda names, files, sym: any(
        n in ("answer", "arrivals", "add", "result", "merge") for n in names)),
    ("rebuild: list upkeep", lambda names, files, sym: "predict" not in sym and any(
        n in ("rebuild_list", "leave_shell") for n in names)),
    ("prediction: the rest (advance, result, loop over the changed)", lambda names, files, sym:
        "predict" in sym or "renew_changed" in sym or "predict" in names),
    ("collision and response", lambda names, files, sym: any(
        n in ("collide_pair", "collide_wall", "pair", "wall", "exchange", "normal_impulse",
              "set_velocity_in_place", "account", "clear") for n in names)),
    ("event loop (pop, stale events, fetching ahead)", lambda names, files, sym:
        "run_until" in sym or "prune" in sym),
]

FN = re.compile(r"^\s*(?:pub(?:\([\w:]+\))?\s+)?(?:const\s+)?(?:unsafe\s+)?fn\s+(\w+)")
_fns = {}


def enclosing_fn(path, line):
    """The function of our sources whose body holds `path`:`line` (the last `fn` above it)."""
    if path not in _fns:
        starts = []
        if os.path.isfile(path):
            for k, text in enumerate(open(path, encoding="utf-8"), start=1):
                if m := FN.match(text):
                    starts.append((k, m.group(1)))
        _fns[path] = starts
    name = None
    for k, n in _fns[path]:
        if k > line:
            break
        name = n
    return name


# The peer's functions, by stage.
PEER = {
    "findcollisions": "predictions",
    "makeneighborlist": "rebuilds (scan and lists)",
    "findneighborlistupdate": "shell exit",
    "addevent": "calendar",
    "addnexteventlist": "calendar",
    "removeevent": "calendar",
    "removeevent.part.0": "calendar",
    "collision": "collision and response",
    "step": "event loop",
    "main": "event loop",
}


def callgrind(cmd, out, cwd=None, instr=False):
    flags = ["--dump-instr=yes"] if instr else []
    r = subprocess.run(["valgrind", "--tool=callgrind", *flags, f"--callgrind-out-file={out}",
                        *cmd], cwd=cwd, capture_output=True, text=True)
    if r.returncode != 0:
        hint = (" (an instruction valgrind cannot run: build for x86-64-v3, not -march=native)"
                if r.returncode == -4 else "")
        sys.exit(f"callgrind_stages.py: {' '.join(cmd)} under valgrind failed with status "
                 f"{r.returncode}{hint}\n{r.stderr[-2000:]}")
    return r.stdout


def own_costs(path, obj):
    """Each instruction's own count (calls' inclusive lines skipped) in objects named `obj`."""
    costs = collections.Counter()
    last, skip, names, ob = [0, 0], False, {}, None

    def pos(tok, k):
        if tok == "*":
            return last[k]
        sign = {"+": 1, "-": -1}.get(tok[0], 0)
        tok = tok[1:] if sign else tok
        v = int(tok, 16) if tok.startswith("0x") else int(tok)
        return last[k] + sign * v if sign else v

    for line in open(path):
        c = line[:1]
        if c.isdigit() or c in "+-*":
            parts = line.split()
            last[0] = pos(parts[0], 0)
            if len(parts) > 2:
                last[1] = pos(parts[1], 1)
            if skip:
                skip = False
            elif ob and obj in ob and len(parts) > 2:
                costs[last[0]] += int(parts[2])
        elif line.startswith(("ob=", "cob=")):
            # An object's name is given once, where it is first named (either line).
            m = re.match(r"c?ob=\((\d+)\)\s*(.*)", line.strip())
            if m.group(2):
                names[m.group(1)] = m.group(2)
            if line.startswith("ob="):
                ob = names.get(m.group(1))
        elif line.startswith("calls="):
            skip = True
    return costs


def collisions(text):
    return int(re.search(r"(\d+) collisions", text).group(1))


def ours(binary, n, phi):
    if not os.access(binary, os.X_OK):
        sys.exit(f"callgrind_stages.py: no binary {binary} (cargo build --release -p "
                 "spheresweep-bench --example sim_rate)")
    with tempfile.TemporaryDirectory() as tmp:
        runs = {}
        for t in ("2", "6"):
            out = os.path.join(tmp, f"cg.{t}")
            text = callgrind([binary, n, phi, t], out, instr=True)
            runs[t] = (own_costs(out, os.path.basename(binary)), collisions(text))
    (short, c2), (long, c6) = runs["2"], runs["6"]
    return stages_of(binary, short, long), c6 - c2


def stages_of(binary, short, long):
    """Each stage's instructions in the longer run less the shorter (`short`, `long`: each
    instruction's own count by address)."""
    dis = subprocess.run(["objdump", "-d", "-l", "--inlines", "--no-show-raw-insn", binary],
                         capture_output=True, text=True, check=True).stdout
    stage = collections.Counter()
    # objdump prints an instruction's source line when it changes, and the chain of callers
    # it is inlined through before every instruction: a chain after an instruction starts
    # again from the last source line.
    sym, source, frames, fresh = "", None, [], True
    for line in dis.splitlines():
        if m := re.match(r"^[0-9a-f]+ <(.*)>:$", line):
            sym = m.group(1)
        elif m := re.match(r"^(/\S+):(\d+)", line):
            source = (m.group(1), int(m.group(2)))
            frames, fresh = [source], False
        elif m := re.match(r"^\s*inlined by (/\S+):(\d+)", line):
            if fresh:
                frames, fresh = [source] if source else [], False
            frames.append((m.group(1), int(m.group(2))))
        elif m := re.match(r"^\s+([0-9a-f]+):\s", line):
            fresh = True
            a = int(m.group(1), 16)
            d = long.get(a, 0) - short.get(a, 0)
            if d:
                ours = [(p, k) for p, k in frames if p and os.path.isfile(p) and "/src/" in p
                        and "/rustc/" not in p and "/.cargo/" not in p]
                names = [enclosing_fn(p, k) for p, k in ours]
                files = " ".join(os.path.basename(p) for p, _ in ours)
                name = next((s for s, rule in STAGES if rule(names, files, sym)), "other")
                stage[name] += d
    return stage


def peer(short_dir, long_dir):
    for d in (short_dir, long_dir):
        if not os.access(os.path.join(d, "md"), os.X_OK):
            sys.exit(f"callgrind_stages.py: no peer binary {os.path.join(d, 'md')} "
                     "(build it with scripts/edmd_peer.sh and a BUILD_DIR)")
    counts = []
    for d in (short_dir, long_dir):
        out = os.path.join(d, "callgrind.stages")
        text = callgrind(["./md"], out, cwd=d)
        table = subprocess.run(["callgrind_annotate", "--inclusive=no", "--threshold=100", out],
                               capture_output=True, text=True, check=True).stdout
        own = collections.Counter()
        for line in table.splitlines():
            if m := re.match(r"\s*([\d,]+) .*?\s(\S+):(\S+) \[.*/md\]", line):
                own[PEER.get(m.group(3), "other")] += int(m.group(1).replace(",", ""))
        counts.append((own, int(re.findall(r"Collisions: (\d+)", text)[-1])))
    (a, ca), (b, cb) = counts
    return collections.Counter({k: b[k] - a[k] for k in b}), cb - ca


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "ours":
        stage, dc = ours(*sys.argv[2:])
    elif len(sys.argv) == 4 and sys.argv[1] == "peer":
        stage, dc = peer(*sys.argv[2:])
    else:
        sys.exit(__doc__)
    for name, v in stage.most_common():
        print(f"{v / dc:8.0f}  {name}")
    print(f"{sum(stage.values()) / dc:8.0f}  total ({dc} collisions)")


if __name__ == "__main__":
    main()
