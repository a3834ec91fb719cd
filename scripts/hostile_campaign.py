#!/usr/bin/env python3
"""Issue 28's hostile-user campaign, re-runnable: mutated scenes, hand-written inputs, kills and
full or read-only disks, each classified as a crash, a hang, a refusal (with a good or a poor
message), an accepted scene that ran, a wrong accept, or work lost (docs/hardening_campaign.md
says what each oracle is and what the last run found).

    cmake --build build --target kiln fuzz_driver
    nice -n 10 /usr/bin/python3 scripts/hostile_campaign.py [--quick] [--out DIR] [--parts abcd]

Python 3 standard library only, with two optional modules, both guarded: PyYAML (the YAML
oracle of part a; without it that oracle is skipped and the summary says so) and h5py (frame
counts and the bit-for-bit comparison of parts c and d; Debian's python3-h5py, in
/usr/bin/python3). Everything is drawn from fixed seeds (--seed), so a re-run makes the same
inputs; timings, and so the moments of the kills, vary with the machine's load.

Writes DIR/results.json (every input, its command lines, exit codes, times, messages and
verdict), DIR/summary.json and DIR/summary.md (the table printed at the end), and keeps the
inputs (DIR/inputs/) so that any finding can be replayed by hand.
"""
import argparse
import hashlib
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

try:
    import yaml  # optional: the YAML oracle
except ImportError:  # pragma: no cover
    yaml = None
try:
    import h5py  # optional: frame counts and bit-for-bit comparisons
    import numpy
except ImportError:  # pragma: no cover
    h5py = None

REPO = Path(__file__).resolve().parent.parent
CHECK_TIMEOUT = 20.0   # s: a check that takes longer is a hang (the bound of tests/scene/hostile_input_test.cpp)
RUN_TIMEOUT = 30.0     # s: a short run (at most SHORT_STEPS steps) that takes longer is a hang
SHORT_STEPS = 200      # steps of a mutated scene's short run
MESSAGE_BOUND = 4096   # bytes: a longer refusal is a poor message
AS_LIMIT = 8 << 30     # bytes of address space for every kiln process (a runaway read is refused, not OOM-killed)
CRASH_MARKERS = ("terminate called", "AddressSanitizer", "runtime error:", "Traceback (most recent call last)",
                 "HDF5-DIAG", "Segmentation fault", "double free", "stack smashing", "Assertion")


# ------------------------------------------------------------------------------------------------
# Processes

def run_proc(argv, timeout, cwd=None, fsize=None, env_extra=None, stdin_path=None, keep=65536):
    """Runs argv in a session of its own with an address-space limit (and a file-size limit, with
    SIGXFSZ ignored, when fsize is given: a write past it fails as on a full disk). Returns the exit
    code, the signal, the wall time, the peak RSS and stdout/stderr (their first `keep` bytes and
    their lengths). A process still running after `timeout` s is killed with its group."""
    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (AS_LIMIT, AS_LIMIT))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if fsize is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    env = dict(os.environ)
    if env_extra:
        env.update(env_extra)
    tag = "%d_%d" % (os.getpid(), time.monotonic_ns())
    out_path, err_path = Path("/tmp/hc_out_" + tag), Path("/tmp/hc_err_" + tag)
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        stdin = open(stdin_path, "rb") if stdin_path else subprocess.DEVNULL
        t0 = time.monotonic()
        p = subprocess.Popen([str(a) for a in argv], cwd=cwd, stdout=out, stderr=err, stdin=stdin, env=env,
                             preexec_fn=limits, start_new_session=True)
        if stdin_path:
            stdin.close()
        status, usage, timed_out = wait_for(p, timeout)
        secs = time.monotonic() - t0
    res = outcome(status, usage, timed_out, secs)
    for name, path in (("stdout", out_path), ("stderr", err_path)):
        data = path.read_bytes()
        res[name + "_len"] = len(data)
        res[name] = data[:keep].decode("utf-8", "replace")
        path.unlink()
    res["argv"] = [str(a) for a in argv]
    return res


def wait_for(p, timeout, ready=None):
    """Waits for p; kills its group after timeout s. Returns (status, rusage, timed_out)."""
    deadline = time.monotonic() + timeout
    timed_out = False
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid == p.pid:
            break
        if time.monotonic() > deadline and not timed_out:
            timed_out = True
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            pid, status, usage = os.wait4(p.pid, 0)
            break
        time.sleep(0.005)
    p.returncode = 0  # reaped here: keep subprocess from waiting again
    return status, usage, timed_out


def outcome(status, usage, timed_out, secs):
    sig = os.WTERMSIG(status) if os.WIFSIGNALED(status) else 0
    rc = os.WEXITSTATUS(status) if os.WIFEXITED(status) else None
    return {"rc": rc, "signal": sig, "timeout": timed_out, "secs": round(secs, 3), "maxrss_mb": round(usage.ru_maxrss / 1024, 1)}


def crashed(r):
    return (not r["timeout"]) and (r["signal"] != 0 or r["rc"] == 6 or r["rc"] not in (0, 1, 2, 3, 4, 5, 130, 143) or
                                   any(m in r["stderr"] for m in CRASH_MARKERS))


# ------------------------------------------------------------------------------------------------
# YAML oracle (PyYAML's parser with the YAML 1.2 core schema's resolvers, which kiln claims)

CORE_TAGS = {"tag:yaml.org,2002:" + t for t in ("str", "int", "float", "bool", "null", "map", "seq", "merge")}


class Tagged:
    def __init__(self, tag, value):
        self.tag, self.value = tag, value


def make_loader():
    if yaml is None:
        return None

    class CoreLoader(yaml.SafeLoader):
        pass
    CoreLoader.yaml_implicit_resolvers = {}
    res = [("tag:yaml.org,2002:bool", r"^(?:true|True|TRUE|false|False|FALSE)$", list("tTfF")),
           ("tag:yaml.org,2002:int", r"^(?:[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$", list("-+0123456789")),
           ("tag:yaml.org,2002:float",
            r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$",
            list("-+.0123456789")),
           ("tag:yaml.org,2002:null", r"^(?:~|null|Null|NULL|)$", ["~", "n", "N", ""]),
           ("tag:yaml.org,2002:merge", r"^(?:<<)$", ["<"])]
    for tag, rx, first in res:
        CoreLoader.add_implicit_resolver(tag, re.compile(rx), first)

    def c_int(loader, node):
        v = loader.construct_scalar(node)
        if v.startswith("0o"):
            return int(v[2:], 8)
        if v.startswith("0x"):
            return int(v[2:], 16)
        try:
            return int(v)
        except ValueError:
            return Tagged(node.tag, v)

    def c_float(loader, node):
        v = loader.construct_scalar(node).lower()
        if v.endswith(".inf"):
            return -math.inf if v.startswith("-") else math.inf
        if v == ".nan":
            return math.nan
        try:
            return float(v)
        except ValueError:
            return Tagged(node.tag, v)

    def c_bool(loader, node):
        v = loader.construct_scalar(node).lower()
        return True if v == "true" else False if v == "false" else Tagged(node.tag, v)

    def c_other(loader, suffix, node):
        if isinstance(node, yaml.ScalarNode):
            return Tagged(node.tag, loader.construct_scalar(node))
        if isinstance(node, yaml.SequenceNode):
            return Tagged(node.tag, loader.construct_sequence(node))
        return Tagged(node.tag, loader.construct_mapping(node))
    CoreLoader.add_constructor("tag:yaml.org,2002:int", c_int)
    CoreLoader.add_constructor("tag:yaml.org,2002:float", c_float)
    CoreLoader.add_constructor("tag:yaml.org,2002:bool", c_bool)
    CoreLoader.add_multi_constructor("", c_other)
    return CoreLoader


LOADER = make_loader()


def yaml_read(text):
    """What the YAML 1.2 core schema makes of `text`: {'docs': [...], 'tags': [...], 'error': str|None}."""
    out = {"docs": [], "tags": [], "error": None}
    if LOADER is None:
        out["error"] = "no PyYAML"
        return out
    # PyYAML is a YAML 1.1 parser: NEL, LS and PS are line breaks there, ordinary characters in YAML
    # 1.2 (which kiln claims). Read as 1.2 reads them: as characters (a space is one).
    text = text.replace("\x85", " ").replace("\u2028", " ").replace("\u2029", " ")
    try:
        nodes = list(yaml.compose_all(text, Loader=LOADER))
        seen, stack = set(), list(nodes)
        while stack and len(seen) < 200000:
            n = stack.pop()
            if n is None or id(n) in seen:
                continue
            seen.add(id(n))
            if n.tag not in CORE_TAGS:
                out["tags"].append(n.tag)
            elif (isinstance(n, yaml.ScalarNode) and n.tag == "tag:yaml.org,2002:null" and
                  n.value not in ("", "~", "null", "Null", "NULL")):  # `!!null 300.0`: null, whatever it says
                out["tags"].append("!!null on '%s'" % n.value[:20])
            if isinstance(n, yaml.SequenceNode):
                stack.extend(n.value)
            elif isinstance(n, yaml.MappingNode):
                for k, v in n.value:
                    stack += [k, v]
        out["docs"] = list(yaml.load_all(text, Loader=LOADER))
    except RecursionError:
        out["error"] = "RecursionError"
    except Exception as e:  # noqa: BLE001 (a parser's verdict, whatever its class)
        out["error"] = "%s: %s" % (type(e).__name__, str(e).splitlines()[0] if str(e) else "")
    return out


def kind_of(v):
    if isinstance(v, bool):
        return "bool"
    if isinstance(v, (int, float)):
        return "num"
    if isinstance(v, str):
        return "str"
    if v is None:
        return "null"
    if isinstance(v, dict):
        return "map"
    if isinstance(v, list):
        return "seq"
    if isinstance(v, bytes):
        return "bytes"
    if isinstance(v, Tagged):
        return "tagged"
    return type(v).__name__


def paths_of(doc, budget=20000):
    """{dotted path: kind} of a constructed document, at most `budget` entries (aliases make DAGs)."""
    out, stack, on_path = {}, [("", doc, ())], set()
    while stack and len(out) < budget:
        path, v, ancestors = stack.pop()
        out[path] = kind_of(v)
        if id(v) in ancestors:
            continue
        if isinstance(v, dict):
            for k, x in v.items():
                stack.append(((path + "." if path else "") + str(k), x, ancestors + (id(v),)))
        elif isinstance(v, list):
            for i, x in enumerate(v):
                stack.append(((path + "." if path else "") + str(i), x, ancestors + (id(v),)))
    return out


def yaml_oracle(text, base_paths, summary, frames):
    """Reasons the scene kiln accepted means something else as YAML (empty: none found)."""
    if LOADER is None:
        return []
    y = yaml_read(text.split("\n#--set\n")[0])
    why = []
    if y["error"]:
        # kiln read what a YAML parser refuses: a disagreement to look at (docs: triage)
        return ["Y2 PyYAML refuses the text kiln accepted: " + y["error"][:200]]
    docs = y["docs"]
    if len(docs) > 1:
        why.append("Y1 %d YAML documents; kiln read one" % len(docs))
    if y["tags"]:
        why.append("Y3 tags beyond the core schema, or !!null on a value: " + ", ".join(sorted(set(y["tags"])))[:200])
    doc = docs[0] if docs else None
    if isinstance(doc, dict) and base_paths:
        mine = paths_of(doc)
        changed = [p for p, k in mine.items() if base_paths.get(p) in ("num", "bool") and k in ("str", "bytes", "tagged")]
        if changed:
            why.append("Y3 number or truth value given as text at " + ", ".join(sorted(changed)[:5]))
    if isinstance(doc, dict) and summary:
        for key, skey in (("dt", "dt"), ("integrator", "integrator"), ("name", "scene")):
            if key in doc and not isinstance(doc[key], (dict, list, Tagged)) and skey in summary:
                a, b = doc[key], summary[skey]
                if key != "dt" and isinstance(a, (int, float)):  # `name: 1.0`: kiln takes the scalar's text, as meant
                    continue
                same = (abs(a - b) <= 1e-12 * abs(a)) if isinstance(a, (int, float)) and isinstance(b, (int, float)) else a == b
                if not same:
                    why.append("Y4 %s is %r as YAML, kiln ran %r" % (key, a, b))
        oi = doc.get("output_interval")
        if (frames is not None and isinstance(oi, (int, float)) and not isinstance(oi, bool) and oi > 0 and
                "freeze" not in doc and "rtol" not in doc):
            t, steps = summary.get("t_end"), summary.get("steps")
            if isinstance(t, (int, float)) and isinstance(steps, int) and t > 0:
                n = min(math.floor(t / oi * (1 + 1e-9)), steps)
                if not (n - 1 <= frames <= n + 3):
                    why.append("Y4 %d frames where output_interval %g over %g s makes about %d" % (frames, oi, t, n + 1))
    return why


# ------------------------------------------------------------------------------------------------
# Judging one scene or command

def message_quality(r, names):
    """Problems of a refusal's message: empty, too long, naming nothing, a crash's marks."""
    err = r["stderr"].strip()
    if not err and r["stdout"].lstrip().startswith("{"):  # kiln check --json: a refusal's reasons are its warnings
        try:
            err = "\n".join(json.loads(r["stdout"]).get("warnings", []))
        except ValueError:
            pass
    bad = []
    if not err:
        bad.append("no message")
    if r["stderr_len"] >= MESSAGE_BOUND:
        bad.append("message of %d bytes" % r["stderr_len"])
    if err and names and not any(n and n in err for n in names):
        bad.append("names none of " + ", ".join(n for n in names if n)[:120])
    if any(m in err for m in CRASH_MARKERS):
        bad.append("crash marks in the message")
    return bad


def judge_scene(check, run, why_wrong, names, expect="either"):
    """The verdict of a scene: check, then (when accepted) a short run."""
    if check["timeout"]:
        return "hang", ["check ran past %g s" % CHECK_TIMEOUT]
    if crashed(check):
        return "crash", ["check: exit %s signal %s" % (check["rc"], check["signal"])]
    if check["rc"] in (1, 2):
        if expect == "accept":
            return "wrong_refusal", ["check refused a scene it should take: " + check["stderr"].strip()[:300]]
        # exit 1 (dt or the step count refused) names the step, not the file
        bad = message_quality(check, list(names) + (["dt", "step"] if check["rc"] == 1 else []))
        return ("refused_poor_message", bad) if bad else ("refused", [])
    if check["rc"] != 0:
        return "crash", ["check: exit %s" % check["rc"]]
    if run is None:
        return ("wrong_accept", why_wrong) if why_wrong else ("accepted", [])
    if run["timeout"]:
        return "hang", ["run of at most %d steps ran past %g s" % (SHORT_STEPS, RUN_TIMEOUT)]
    if crashed(run):
        return "crash", ["run: exit %s signal %s: %s" % (run["rc"], run["signal"], run["stderr"].strip()[-300:])]
    why = list(why_wrong)
    if run["rc"] == 3:
        why.append("R1 check accepted, the run stopped unstable in its first %d steps: %s" %
                   (SHORT_STEPS, run["stderr"].strip()[:400]))
    elif run["rc"] in (1, 2):
        why.append("R2 check accepted, the run refused (exit %d): %s" % (run["rc"], run["stderr"].strip()[:400]))
    elif run["rc"] != 0:
        why.append("R3 run exit %d: %s" % (run["rc"], run["stderr"].strip()[:300]))
    if expect == "refuse" and not why:
        why.append("E accepted an input that must be refused")
    if why:
        return "wrong_accept", why
    return "ok", []


class Kiln:
    def __init__(self, binary, driver):
        self.bin, self.driver = str(binary), str(driver) if driver else None

    def check(self, scene, sets=(), extra=()):
        argv = [self.bin, "check", scene, "--json"] + list(extra)
        for s in sets:
            argv += ["--set", s]
        return run_proc(argv, CHECK_TIMEOUT, env_extra={"OMP_NUM_THREADS": "1"})

    def short_run(self, scene, out, dt, t_end, sets=(), extra=()):
        t = SHORT_STEPS * dt
        if isinstance(t_end, (int, float)) and not isinstance(t_end, bool) and 0 < t_end < t:
            t = t_end
        argv = [self.bin, "run", scene, "--quiet", "--out", out, "--t-end", repr(t)] + list(extra)
        for s in sets:
            argv += ["--set", s]
        return run_proc(argv, RUN_TIMEOUT, env_extra={"OMP_NUM_THREADS": "1"})


def frames_in(path):
    if h5py is None or not Path(path).exists():
        return None
    try:
        with h5py.File(path, "r") as f:
            return int(f["time"].shape[0])
    except Exception:  # noqa: BLE001
        return -1


def scene_case(kiln, scene_path, text, work, base_paths=None, expect="either", names=None, extra=()):
    """check + short run + oracles of one scene file; returns its record."""
    sets = []
    if "\n#--set\n" in text:
        sets = [s for s in text.split("\n#--set\n", 1)[1].splitlines() if s.strip()]
    check = kiln.check(scene_path, sets, extra)
    rec = {"check": slim(check)}
    run = None
    summary, frames = None, None
    if check["rc"] == 0 and not check["timeout"] and not crashed(check):
        try:
            dt = float(json.loads(check["stdout"])["dt"])
        except Exception:  # noqa: BLE001
            dt = None
        t_end = None
        y = yaml_read(text.split("\n#--set\n")[0]) if LOADER else {"docs": []}
        if y["docs"] and isinstance(y["docs"][0], dict):
            t_end = y["docs"][0].get("t_end")
        out = Path(work) / "run"
        shutil.rmtree(out, ignore_errors=True)
        if dt and dt > 0 and math.isfinite(dt):
            run = kiln.short_run(scene_path, out, dt, t_end, sets, extra)
            rec["run"] = slim(run)
            try:
                summary = json.loads((out / "summary.json").read_text())
            except Exception:  # noqa: BLE001
                summary = None
            frames = frames_in(out / "result.h5")
            rec["frames"] = frames
        else:
            rec["note"] = "check --json gave no usable dt: %r" % check["stdout"][:200]
        shutil.rmtree(out, ignore_errors=True)
    why = yaml_oracle(text, base_paths, summary if not sets else None, frames) if check["rc"] == 0 else []
    verdict, reasons = judge_scene(check, run, why, names or [Path(scene_path).name], expect)
    rec.update({"verdict": verdict, "reasons": reasons})
    return rec


def slim(r):
    s = dict(r)
    s["stdout"] = s["stdout"][:2000]
    s["stderr"] = s["stderr"][:4000]
    return s


# ------------------------------------------------------------------------------------------------
# Part a: mutated scenes

NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")
KEYLINE = re.compile(r"^(\s*)(?:- )?([A-Za-z_][\w]*):(\s*)(.*)$")
EDGE_NUMBERS = ["0", "-0", "-1", "1e300", "-1e300", "1e-300", "1e308", "2e308", "1e-320", "5e-324", ".nan", ".inf",
                "-.inf", "nan", "inf", "NaN", "1e999", "0x1F", "0o17", "017", "1_000", "1:30", "+1", "1e", ".5", "5.",
                "9223372036854775807", "9223372036854775808", "18446744073709551617", "4294967298", "2147483648",
                "-2147483649", "yes", "true", "~", "null", "''", "[]", "{}"]
TAGS = ["!!str", "!!binary", "!custom", "!!float", "!!int", "!!null", "!!bool", "!<tag:yaml.org,2002:str>", "!!map",
        "!!seq", "!local", "!!timestamp", "!!python/object/apply:os.system", "!!set"]
HUGE_COUNTS = ["16777217", "100000000", "1000000000000", "1e19", "9223372036854775807", "18446744073709551616",
               "4294967298", "-1", "0", "2.5", "1e6"]
INTERVALS = ["1e-300", "5e-324", "1e-12", "1e-9", "0", "-1", "1e300", ".nan"]
DTS = ["1e-300", "5e-324", "2.2250738585072014e-308", "1e-15", "1e-9", "1e-3", "1", "1e3", "1e300"]


def code_span(line):
    """The part of a line before a comment (a # after a space or at the start)."""
    m = re.search(r"(^|\s)#", line)
    return line[:m.start()] if m else line


def pick_number(lines, rng):
    spots = [(i, m) for i, l in enumerate(lines) for m in NUMBER.finditer(code_span(l))]
    return rng.choice(spots) if spots else None


def replace_span(line, m, new):
    return line[:m.start()] + new + line[m.end():]


def set_key(text, key, value, rng):
    """Sets every `key:` value (block or flow) to value; adds it at the top level if absent."""
    pat = re.compile(r"(?<![\w.])(%s:\s*)([^,}\n#]+)" % re.escape(key))
    hits = list(pat.finditer(text))
    if not hits:
        return text.rstrip("\n") + "\n%s: %s\n" % (key, value)
    m = rng.choice(hits)
    return text[:m.start(2)] + value + text[m.end(2):]


def op_number(text, rng):
    lines = text.split("\n")
    spot = pick_number(lines, rng)
    if not spot:
        return text, "number: none"
    i, m = spot
    u = rng.random()
    try:
        v = float(m.group())
    except ValueError:
        v = 1.0
    if u < 0.3:
        new = rng.choice(EDGE_NUMBERS)
    elif u < 0.5:
        new = repr(v * 10.0 ** rng.randint(-30, 30))
    else:  # a careless user's edit: a factor of 0.3 to 3, a digit more or less, a sign
        new = rng.choice([repr(v * rng.uniform(0.3, 3.0)), m.group() + "0", m.group()[:-1] or "0", repr(-v),
                          repr(round(v * rng.uniform(0.8, 1.2), 3))])
    lines[i] = replace_span(lines[i], m, new)
    return "\n".join(lines), "number %s -> %s (line %d)" % (m.group(), new, i + 1)


def op_key_delete(text, rng):
    lines = text.split("\n")
    keys = [i for i, l in enumerate(lines) if KEYLINE.match(l) and not l.lstrip().startswith("#")]
    if not keys:
        return text, "delete: none"
    i = rng.choice(keys)
    indent = len(lines[i]) - len(lines[i].lstrip(" -"))
    j = i + 1
    while j < len(lines) and (not lines[j].strip() or len(lines[j]) - len(lines[j].lstrip(" ")) > indent):
        j += 1
    key = KEYLINE.match(lines[i]).group(2)
    if lines[i].lstrip().startswith("- "):  # an item's first key: keep the item's dash
        rest = lines[i + 1:j]
        del lines[i:j]
        if rest:
            lines.insert(i, " " * (len(lines[i - 1]) - len(lines[i - 1].lstrip())) + "- " + rest[0].lstrip())
            lines[i + 1:i + 1] = rest[1:]
    else:
        del lines[i:j]
    return "\n".join(lines), "delete key %s (line %d)" % (key, i + 1)


def op_key_duplicate(text, rng):
    lines = text.split("\n")
    keys = [i for i, l in enumerate(lines) if KEYLINE.match(l) and not l.lstrip().startswith(("#", "- "))]
    if not keys:
        return text, "duplicate: none"
    i = rng.choice(keys)
    lines.insert(i + 1, lines[i])
    return "\n".join(lines), "duplicate line %d" % (i + 1)


def op_tag(text, rng):
    lines = text.split("\n")
    spot = pick_number(lines, rng)
    if not spot:
        return text, "tag: none"
    i, m = spot
    tag = rng.choice(TAGS)
    value = "aGVsbG8=" if tag == "!!binary" and rng.random() < 0.5 else m.group()
    lines[i] = replace_span(lines[i], m, tag + " " + value)
    return "\n".join(lines), "tag %s on %s (line %d)" % (tag, m.group(), i + 1)


def op_quote(text, rng):
    lines = text.split("\n")
    spot = pick_number(lines, rng)
    if not spot:
        return text, "quote: none"
    i, m = spot
    q = rng.choice(["'", '"'])
    lines[i] = replace_span(lines[i], m, q + m.group() + q)
    return "\n".join(lines), "quote %s (line %d)" % (m.group(), i + 1)


def op_second_document(text, rng):
    choice = rng.randrange(6)
    if choice == 0:
        return text.rstrip("\n") + "\n---\nname: second\n", "second document (name: second)"
    if choice == 1:
        return text.rstrip("\n") + "\n---\n" + text, "second document (the scene again)"
    if choice == 2:
        return text.rstrip("\n") + "\n---\n", "second document (empty, after ---)"
    if choice == 3:
        return "---\n" + text, "leading --- (one document)"
    if choice == 4:
        return text.rstrip("\n") + "\n...\n", "document end marker ... (one document)"
    lines = text.split("\n")
    at = rng.randrange(1, max(2, len(lines)))
    return "\n".join(lines[:at] + ["---"] + lines[at:]), "--- inserted at line %d" % (at + 1)


def op_line_breaks(text, rng):
    choice = rng.randrange(6)
    if choice in (0, 1):  # a lone CR ending a comment: the next line's key hides behind it when CR is no break
        spots = [m.end() for m in re.finditer(r"#[^\n]*\n", text)]
        if spots:
            k = rng.choice(spots) - 1
            return text[:k] + "\r" + text[k + 1:], "lone CR ending a comment (offset %d)" % k
    if choice == 2:
        return text.replace("\n", "\r\n"), "CRLF throughout"
    if choice == 3:
        return text.replace("\n", "\r"), "CR only throughout"
    if choice == 4:  # YAML 1.1's other line breaks, which YAML 1.2 reads as characters
        spots = [m.end() for m in re.finditer(r"#[^\n]*\n", text)]
        if spots:
            k = rng.choice(spots) - 1
            ch = rng.choice(["\u0085", "\u2028", "\u2029"])
            return text[:k] + ch + text[k + 1:], "U+%04X ending a comment (YAML 1.1 break only)" % ord(ch)
    k = rng.randrange(len(text)) if text else 0
    return text[:k] + "\r" + text[k:], "lone CR at offset %d" % k


def op_bom_nul(text, rng):
    choice = rng.randrange(4)
    if choice == 0:
        return "\ufeff" + text, "UTF-8 BOM at start"
    k = rng.randrange(len(text) + 1)
    if choice == 1:
        return text[:k] + "\x00" + text[k:], "NUL byte at offset %d" % k
    if choice == 2:
        return text[:k] + "\ufeff" + text[k:], "BOM inside at offset %d" % k
    return text + "\x00" * rng.choice([1, 100, 100000]), "NUL bytes at the end"


def op_deep(text, rng):
    d = rng.choice([5, 63, 64, 65, 200, 10000, 200000])
    if rng.random() < 0.5:
        return set_key(text, "gravity", "[" * d + "0, -9.81" + "]" * d, rng), "gravity nested %d deep (flow)" % d
    d = min(d, 3000)
    block = "".join("\n" + "  " * (k + 1) + "a:" for k in range(d)) + " 1"
    return text.rstrip("\n") + "\nextra:" + block + "\n", "block map nested %d deep" % d


def op_alias(text, rng):
    choice = rng.randrange(6)
    mat = re.search(r"^materials:\s*\n", text, re.M)
    if choice == 0 and mat:  # issue 28's
        k = mat.end()
        return text[:k] + "  base: &base {<<: *base, density: 1}\n" + text[k:], "self-merging anchor in materials"
    if choice == 1 and mat:
        m = re.search(r"^(  )(\w+):\s*(\{[^\n]*\})\s*$", text[mat.end():], re.M)
        if m:
            k = mat.end() + m.start(3)
            t = text[:k] + "&m " + text[k:]
            return t.rstrip("\n") + "\n", "anchor on material %s (unused)" % m.group(2)
    if choice == 2:
        laughs = "lol0: &l0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n" + "".join(
            "lol%d: &l%d [%s]\n" % (k, k, ", ".join(["*l%d" % (k - 1)] * 10)) for k in range(1, 9))
        return laughs + text, "billion laughs (10^9 items) before the scene"
    if choice == 3:
        return set_key(text, "gravity", "&g [0, *g]", rng), "alias inside its own anchor (gravity)"
    if choice == 4:
        return set_key(text, "dt", "*nowhere", rng), "alias to no anchor"
    # an anchor on one number, an alias to it elsewhere
    lines = text.split("\n")
    spots = [(i, m) for i, l in enumerate(lines) for m in NUMBER.finditer(code_span(l))]
    if len(spots) >= 2:
        (i, m), (j, n) = rng.sample(spots, 2)
        if (i, m.start()) > (j, n.start()):
            (i, m), (j, n) = (j, n), (i, m)
        lines[j] = replace_span(lines[j], n, "*x")
        lines[i] = replace_span(lines[i], m, "&x " + m.group())
        return "\n".join(lines), "anchor line %d, alias line %d" % (i + 1, j + 1)
    return text, "alias: none"


def op_counts(text, rng):
    key = rng.choice(["count", "rows", "columns", "attempts", "seed"])
    value = rng.choice(HUGE_COUNTS)
    if key not in text:
        return text, "count: no %s" % key
    return set_key(text, key, value, rng), "%s: %s" % (key, value)


def op_interval(text, rng):
    key = rng.choice(["output_interval", "output_interval", "dt", "t_end", "skin"])
    value = rng.choice(INTERVALS if key != "dt" else DTS)
    return set_key(text, key, value, rng), "%s: %s" % (key, value)


def op_stiffness(text, rng):
    keys = [k for k in ("stiffness", "youngs_modulus", "density", "conductivity", "rpm", "restitution") if k + ":" in text]
    if not keys:
        return text, "stiffness: none"
    key = rng.choice(keys)
    value = rng.choice(["1e300", "1e-300", "1e308", "1e200", "1e150", "1e-150"])
    return set_key(text, key, value, rng), "%s: %s" % (key, value)


def op_bytes(text, rng):
    data = bytearray(text.encode("utf-8", "surrogatepass"))
    n = rng.randint(1, 4)
    for _ in range(n):
        if data:
            data[rng.randrange(len(data))] = rng.randrange(256)
    return data.decode("latin-1"), "%d random bytes" % n  # latin-1: the bytes as they are (write_scene keeps them)


def op_truncate(text, rng):
    k = rng.randrange(len(text) + 1)
    return text[:k], "cut at offset %d of %d" % (k, len(text))


def op_indent(text, rng):
    lines = text.split("\n")
    cand = [i for i, l in enumerate(lines) if l.strip() and not l.lstrip().startswith("#")]
    if not cand:
        return text, "indent: none"
    i = rng.choice(cand)
    choice = rng.randrange(3)
    if choice == 0:
        lines[i] = "\t" + lines[i].lstrip(" ")
        what = "tab indent"
    elif choice == 1:
        lines[i] = " " + lines[i]
        what = "one more space"
    else:
        lines[i] = lines[i][1:] if lines[i].startswith(" ") else lines[i]
        what = "one space less"
    return "\n".join(lines), "%s at line %d" % (what, i + 1)


def op_reorder(text, rng):
    """Two top-level blocks swapped: the same scene."""
    lines = text.split("\n")
    starts = [i for i, l in enumerate(lines) if re.match(r"^[A-Za-z_]\w*:", l)]
    if len(starts) < 2:
        return text, "reorder: none"
    blocks, bounds = [], starts + [len(lines)]
    head = lines[:starts[0]]
    for a, b in zip(bounds, bounds[1:]):
        blocks.append(lines[a:b])
    i, j = rng.sample(range(len(blocks)), 2)
    blocks[i], blocks[j] = blocks[j], blocks[i]
    return "\n".join(head + [l for blk in blocks for l in blk]), "top-level blocks %d and %d swapped" % (i, j)


def op_comment(text, rng):
    """A comment added at the end of a random line, or a '#' inside a value."""
    lines = text.split("\n")
    i = rng.randrange(len(lines))
    if rng.random() < 0.7:
        lines[i] = lines[i] + " # a note: key: 1"
        return "\n".join(lines), "comment after line %d" % (i + 1)
    lines[i] = lines[i].replace(" ", " #", 1)
    return "\n".join(lines), "'#' inside line %d" % (i + 1)


def op_long_text(text, rng):
    key = rng.choice(["name", "integrator", "description"])
    n = rng.choice([101, 1001, 100000, 3000000])
    return set_key(text, key, "x" * n, rng), "%s of %d characters" % (key, n)


TEXT_OPS = [op_number, op_number, op_number, op_number, op_reorder, op_comment, op_key_delete, op_key_duplicate, op_tag, op_quote, op_second_document,
            op_line_breaks, op_bom_nul, op_deep, op_alias, op_counts, op_interval, op_interval, op_stiffness, op_bytes,
            op_truncate, op_indent, op_long_text]


def structural(kiln, text, seed, rounds):
    if not kiln.driver:
        return text, "structural: no fuzz_driver"
    p = subprocess.run([kiln.driver, "mutate", str(seed), str(rounds)], input=text.encode("utf-8", "surrogatepass"),
                       capture_output=True, timeout=60)
    if p.returncode != 0:
        return text, "structural: fuzz_driver exit %d" % p.returncode
    return p.stdout.decode("utf-8", "surrogateescape"), "structural x%d (seed %d)" % (rounds, seed)


def write_scene(path, text):
    try:
        data = text.encode("utf-8", "surrogateescape")
    except UnicodeEncodeError:
        data = text.encode("utf-8", "surrogatepass")
    path.write_bytes(data)


def part_a(kiln, out, n, seed, log):
    cases = sorted(p for p in (REPO / "cases").glob("*.yaml"))
    base_text = {c.name: c.read_text() for c in cases}
    base_paths = {}
    for name, t in base_text.items():
        y = yaml_read(t)
        base_paths[name] = paths_of(y["docs"][0]) if y["docs"] and isinstance(y["docs"][0], dict) else {}
    sdir = out / "inputs" / "mutated"
    sdir.mkdir(parents=True, exist_ok=True)
    link = sdir / "geometry"
    if not link.exists():
        link.symlink_to(REPO / "cases" / "geometry")
    work = out / "work" / "a"
    work.mkdir(parents=True, exist_ok=True)
    records = []
    for i in range(n):
        rng = random.Random(seed * 1000003 + i)
        base = cases[i % len(cases)].name
        text = base_text[base]
        ops = []
        style = i % 3
        if style in (0, 2):
            text, what = structural(kiln, text, seed * 7919 + i, rng.choice([1, 1, 1, 2, 3]))
            ops.append(what)
        if style in (1, 2):
            for _ in range(rng.choice([1, 1, 1, 2])):
                op = rng.choice(TEXT_OPS)
                text, what = op(text, rng)
                ops.append(what)
        path = sdir / ("m%04d_%s" % (i, base))
        if any("random bytes" in o for o in ops):  # op_bytes keeps bytes as latin-1 characters
            path.write_bytes(text.encode("latin-1", "replace"))
        else:
            write_scene(path, text)
        text = path.read_bytes().decode("utf-8", "surrogateescape")  # what kiln reads, for the oracle
        rec = scene_case(kiln, str(path), text, work, base_paths[base])
        rec.update({"part": "a", "id": "m%04d" % i, "base": base, "ops": ops, "file": str(path)})
        records.append(rec)
        log(rec)
    return records


# ------------------------------------------------------------------------------------------------
# Part b: hand-written inputs

def t3():
    return (REPO / "cases" / "t3_heap.yaml").read_text()


def sub(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


def csv_scene(csv_name, extra=""):
    text = t3()
    return sub(text, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
               "    file: %s\n%s" % (csv_name, extra))


def lattice_rows(n, spacing=0.005, r=0.001):
    cols = 20
    return ["%.9g,%.9g,%g" % (-0.05 + (k % cols) * spacing, 0.005 + (k // cols) * spacing, r) for k in range(n)]


def handwritten_scenes():
    """(name, text or bytes, expect, extra files {name: bytes or ('sparse', size) or ('fifo',)}, extra argv)."""
    T = t3()
    n3 = (REPO / "cases" / "n3_shear_cell.yaml").read_text()
    mats = "materials:\n"
    S = []
    add = lambda name, text, expect, files=None, extra=(): S.append((name, text, expect, files or {}, list(extra)))
    add("alias_self_merge_t3", sub(T, mats, mats + "  base: &base {<<: *base, density: 1}\n"), "refuse")
    add("alias_self_merge_n3", sub(n3, mats, mats + "  base: &base {<<: *base, density: 1}\n"), "refuse")
    add("alias_self_in_list", sub(T, "gravity: [0, -9.81]", "gravity: &g [0, *g]"), "refuse")
    add("alias_undefined", sub(T, "gravity: [0, -9.81]", "gravity: *nope"), "refuse")
    add("alias_billion_laughs", "lol0: &l0 [1,1,1,1,1,1,1,1,1,1]\n" + "".join(
        "lol%d: &l%d [%s]\n" % (k, k, ",".join(["*l%d" % (k - 1)] * 10)) for k in range(1, 9)) + T, "refuse")
    add("alias_merge_valid", sub(T, "  copper: {density: 8900,", "  copper: &cu {density: 8900,").replace(
        "  wall: {stiffness: 6000, restitution: 0.5, friction: 0.5, rolling_friction: 0.3}",
        "  wall: {<<: *cu, restitution: 0.5, density: 8900}"), "either")
    add("lattice_spacing_typo", sub(T, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
                                    "    radius: 0.001\n    lattice: {kind: hexagonal, origin: [-0.05, 0.005], spacing: 0.0000025, rows: 200, columns: 200}\n"), "refuse")
    add("csv_2M_identical_rows", csv_scene("rows.csv"), "refuse", {"rows.csv": ("rows", "x,y,radius\n", "0.0,0.05,0.001\n", 2000000)})
    add("csv_1GB_sparse", csv_scene("sparse.csv"), "refuse", {"sparse.csv": ("sparse", 1 << 30)})
    add("csv_bom", csv_scene("bom.csv"), "accept", {"bom.csv": ("text", "\ufeffx,y,radius\n" + "\n".join(lattice_rows(100)) + "\n")})
    add("csv_nul_byte", csv_scene("nul.csv"), "refuse", {"nul.csv": ("text", "x,y,radius\n" + "\n".join(lattice_rows(10)).replace("0.001", "0.0\x0001", 1) + "\n")})
    add("csv_crlf", csv_scene("crlf.csv"), "accept", {"crlf.csv": ("text", "x,y,radius\r\n" + "\r\n".join(lattice_rows(50)) + "\r\n")})
    add("csv_nan", csv_scene("nan.csv"), "refuse", {"nan.csv": ("text", "x,y,radius\n" + "\n".join(lattice_rows(10)).replace("0.001", "nan", 1) + "\n")})
    add("csv_no_radius_column", csv_scene("norad.csv"), "refuse", {"norad.csv": ("text", "x,y\n0,0.05\n0.01,0.05\n")})
    add("csv_long_line", csv_scene("long.csv"), "refuse", {"long.csv": ("text", "x,y,radius\n0,0.05," + "1" * 1000000 + "\n")})
    add("csv_header_only", csv_scene("empty.csv"), "refuse", {"empty.csv": ("text", "x,y,radius\n")})
    add("csv_dev_zero", csv_scene("/dev/zero"), "refuse")
    add("csv_dev_zero_format_csv", csv_scene("/dev/zero", "    format: csv\n"), "refuse")
    add("csv_fifo_format_csv", csv_scene("pipe", "    format: csv\n"), "refuse", {"pipe": ("fifo",)})
    add("csv_fifo", csv_scene("pipe.csv"), "refuse", {"pipe.csv": ("fifo",)})
    add("csv_directory", csv_scene("adir.csv"), "refuse", {"adir.csv": ("dir",)})
    add("csv_missing", csv_scene("missing.csv"), "refuse")
    add("lammps_malformed", csv_scene("pile.data"), "refuse", {"pile.data": ("text", "LAMMPS data\n\n300 atoms\nAtoms # sphere\n\n1 1 0.002\n")})
    add("output_interval_1e-300", sub(T, "output_interval: 0.01", "output_interval: 1.0e-300"), "refuse")
    add("output_interval_5e-324", sub(T, "output_interval: 0.01", "output_interval: 5e-324"), "refuse")
    add("output_interval_1e-9", sub(T, "output_interval: 0.01", "output_interval: 1.0e-9"), "refuse")
    add("stiffness_1e300_copper", sub(T, "density: 8900, stiffness: 6000", "density: 8900, stiffness: 1.0e300"), "either")
    add("stiffness_1e300_both", sub(T, "density: 8900, stiffness: 6000", "density: 8900, stiffness: 1.0e300").replace(
        "wall: {stiffness: 6000", "wall: {stiffness: 1.0e300"), "either")
    add("stiffness_1e-300", sub(T, "density: 8900, stiffness: 6000", "density: 8900, stiffness: 1.0e-300"), "either")
    add("lone_cr_comment_before_output_interval", sub(T, "t_end: 3.0\noutput_interval: 0.01", "t_end: 3.0 # three seconds\routput_interval: 0.01"), "accept")
    add("lone_cr_everywhere", T.replace("\n", "\r"), "accept")
    add("crlf_everywhere", T.replace("\n", "\r\n"), "accept")
    add("nel_ending_comment", sub(T, "t_end: 3.0\noutput_interval: 0.01", "t_end: 3.0 # three seconds\u0085output_interval: 0.01"), "either")
    add("u2028_ending_comment", sub(T, "t_end: 3.0\noutput_interval: 0.01", "t_end: 3.0 # three seconds\u2028output_interval: 0.01"), "either")
    add("second_document", T + "---\nname: second\n", "refuse")
    add("second_document_same_scene", T + "---\n" + T, "refuse")
    add("second_document_empty", T + "---\n", "either")
    add("leading_document_marker", "---\n" + T, "accept")
    add("document_end_marker", T + "...\n", "accept")
    add("tag_str_number", sub(T, "density: 8900", "density: !!str 8900"), "refuse")
    add("tag_binary", sub(T, "density: 8900", "density: !!binary aGVsbG8="), "refuse")
    add("tag_custom", sub(T, "density: 8900", "density: !custom 8900"), "refuse")
    add("tag_verbatim_str", sub(T, "density: 8900", "density: !<tag:yaml.org,2002:str> 8900"), "refuse")
    add("tag_python_object", sub(T, "dt: 2.0e-6", "dt: !!python/object/apply:os.system ['true']"), "refuse")
    add("tag_float_on_number", sub(T, "density: 8900", "density: !!float 8900"), "accept")
    add("tag_int_on_fraction", sub(T, "dt: 2.0e-6", "dt: !!int 2.0e-6"), "refuse")
    add("tag_null_on_dt", sub(T, "dt: 2.0e-6", "dt: !!null 2.0e-6"), "refuse")
    add("tag_seq_on_map", sub(T, "stop: {kinetic", "stop: !!seq {kinetic"), "refuse")
    add("tag_on_name", sub(T, "name: t3_heap", "name: !custom t3_heap"), "refuse")
    add("quoted_density_double", sub(T, "density: 8900", 'density: "8900"'), "refuse")
    add("quoted_density_single", sub(T, "density: 8900", "density: '8900'"), "refuse")
    add("quoted_dt", sub(T, "dt: 2.0e-6", "dt: '2.0e-6'"), "refuse")
    add("quoted_count", sub(T, "count: 300", "count: '300'"), "refuse")
    add("quoted_gravity_item", sub(T, "gravity: [0, -9.81]", "gravity: [0, '-9.81']"), "refuse")
    add("quoted_seed", sub(T, "seed: 3", 'seed: "3"'), "refuse")
    add("yaml11_bool_yes", sub(T, "report: [heap]", "report: [heap]\nallow_overlap: yes"), "either")
    add("yaml11_sexagesimal_count", sub(T, "count: 300", "count: 5:00"), "refuse")
    add("yaml11_underscore_count", sub(T, "count: 300", "count: 3_00"), "refuse")
    add("hex_count", sub(T, "count: 300", "count: 0x12C"), "either")
    add("octal_count", sub(T, "count: 300", "count: 0o454"), "either")
    add("bom_scene", "\ufeff" + T, "accept")
    add("nul_in_scene", sub(T, "name: t3_heap", "name: t3\x00_heap"), "refuse")
    add("nul_in_comment", sub(T, "# T3 (thesis", "# T3\x00 (thesis"), "either")
    add("tab_indentation", sub(T, "    restitution: 0.8", "\trestitution: 0.8"), "refuse")
    add("nesting_100", sub(T, "gravity: [0, -9.81]", "gravity: " + "[" * 100 + "0, -9.81" + "]" * 100), "refuse")
    add("nesting_1e5", sub(T, "gravity: [0, -9.81]", "gravity: " + "[" * 100000 + "0, -9.81" + "]" * 100000), "refuse")
    add("duplicate_key", sub(T, "dt: 2.0e-6", "dt: 2.0e-6\ndt: 1.0e-6"), "refuse")
    add("duplicate_key_flow", sub(T, "density: 8900,", "density: 8900, density: 1,"), "refuse")
    for v in ("1e19", "9223372036854775808", "-1", "2.5", "0", "16777217", "1.0e12"):
        add("count_" + v, sub(T, "count: 300", "count: " + v), "refuse")
    add("lattice_box2d_limit", sub(T, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
                                   "    radius: 0.001\n    lattice: {kind: hexagonal, origin: [-0.05, 0.005], spacing: 0.0025, rows: 4097, columns: 4096}\n"), "refuse")
    add("lattice_columns_wrap", sub(T, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
                                    "    radius: 0.001\n    lattice: {kind: hexagonal, origin: [-0.05, 0.005], spacing: 0.0025, rows: 1, columns: 4294967298}\n"), "refuse")
    for v in ("1.0e-300", "5e-324", "1.0e-320", "1.0e300", "0", "-2.0e-6", ".nan", ".inf"):
        add("dt_" + v, sub(T, "dt: 2.0e-6", "dt: " + v), "refuse")
    add("dt_beyond_limit", sub(T, "dt: 2.0e-6", "dt: 2.0e-4"), "refuse")
    for v in ("1.0e300", "1.0e12", "1.0e-300", "0"):
        add("t_end_" + v, sub(T, "t_end: 3.0", "t_end: " + v), "refuse")
    add("name_100k", sub(T, "name: t3_heap", "name: " + "x" * 100000), "refuse")
    add("name_path", sub(T, "name: t3_heap", "name: ../../../tmp/x"), "refuse")
    add("name_empty", sub(T, "name: t3_heap", 'name: ""'), "refuse")
    add("integrator_3MB", sub(T, "integrator: velocity-verlet", "integrator: " + "v" * 3000000), "refuse")
    add("integrator_typo", sub(T, "integrator: velocity-verlet", "integrator: velocity-verle"), "refuse")
    add("unknown_key", T + "outptu_interval: 0.01\n", "refuse")
    add("empty_file", "", "refuse")
    add("only_comments", "# nothing\n# here\n", "refuse")
    add("scalar_document", "42\n", "refuse")
    add("list_document", "- name: x\n", "refuse")
    add("latin1_name", sub(T, "name: t3_heap", "name: t3_h\xe9ap").encode("latin-1"), "refuse")
    add("restitution_1e-300", sub(T, "restitution: 0.8, friction", "restitution: 1.0e-300, friction"), "refuse")
    add("restitution_1.5", sub(T, "restitution: 0.8, friction", "restitution: 1.5, friction"), "refuse")
    add("gravity_1e300", sub(T, "gravity: [0, -9.81]", "gravity: [0, -1.0e300]"), "refuse")
    add("gravity_1e6", sub(T, "gravity: [0, -9.81]", "gravity: [0, -1.0e6]"), "either")
    add("density_1e300", sub(T, "density: 8900,", "density: 1.0e300,"), "refuse")
    add("coordinates_1e7", sub(T, "[-0.12, 0.15], [-0.12, 0.0]", "[-1.0e7, 0.15], [-0.12, 0.0]"), "refuse")
    add("radius_1e-12", sub(T, "radius: {uniform: [0.001, 0.002]}", "radius: {uniform: [1.0e-12, 0.002]}"), "refuse")
    add("radius_inverted_range", sub(T, "radius: {uniform: [0.001, 0.002]}", "radius: {uniform: [0.002, 0.001]}"), "refuse")
    add("fill_cannot_fit", sub(T, "count: 300", "count: 100000"), "refuse")
    add("fill_attempts_1e12", sub(T, "count: 300, seed: 3", "count: 300, seed: 3, attempts: 1000000000000"), "refuse")
    add("two_discs_same_point", sub(T, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
                                    "    radius: 0.001\n    at: [[0, 0.05], [0, 0.05]]\n"), "refuse")
    add("disc_on_wall", sub(T, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
                            "    radius: 0.001\n    at: [[0, 0.0]]\n"), "refuse")
    add("fast_disc", sub(T, "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
                         "    radius: 0.001\n    velocity: [0, -1.0e5]\n    at: [[0, 0.05]]\n"), "refuse")
    add("temperature_below_absolute_zero", sub(T, "    fill: {rectangle", "    temperature: -300\n    fill: {rectangle"), "refuse")
    add("report_unknown", sub(T, "report: [heap]", "report: [heap, nothing]"), "refuse")
    add("stop_negative", sub(T, "kinetic_energy_below: 1.0e-7", "kinetic_energy_below: -1"), "refuse")
    add("skin_1e300", T + "skin: 1.0e300\n", "refuse")
    add("periodic_tiny", T.replace("walls:\n  - name: floor\n    material: wall\n    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]\n", "periodic: {x: [-0.03, -0.029]}\n"), "refuse")
    add("svg_missing", sub(T, "    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "    svg: {file: missing.svg, scale: 0.001, offset: [0, 0]}"), "refuse")
    add("svg_1GB_sparse", sub(T, "    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "    svg: {file: big.svg, scale: 0.001, offset: [0, 0]}"), "refuse", {"big.svg": ("sparse", 1 << 30)})
    add("svg_malformed", sub(T, "    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "    svg: {file: bad.svg, scale: 0.001, offset: [0, 0]}"), "refuse", {"bad.svg": ("text", "<svg><path d='M 0 0 L")})
    add("svg_entities", sub(T, "    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "    svg: {file: lol.svg, scale: 0.001, offset: [0, 0]}"), "refuse",
        {"lol.svg": ("text", '<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]><svg xmlns="http://www.w3.org/2000/svg"><path d="&c;"/></svg>')})
    add("svg_dev_zero", sub(T, "    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "    svg: {file: /dev/zero, scale: 0.001, offset: [0, 0]}"), "refuse")
    add("svg_huge_path", sub(T, "    polyline: [[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "    svg: {file: huge.svg, scale: 0.001, offset: [-0.1, 0]}"), "either",
        {"huge.svg": ("text", '<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 ' + "l 0.0001 0 " * 200000 + '"/></svg>')})
    return S


def materialise(files, d):
    for name, spec in files.items():
        p = d / name
        if p.exists() or p.is_symlink():
            if p.is_dir():
                p.rmdir()
            else:
                p.unlink()
        kind = spec[0]
        if kind == "text":
            p.write_bytes(spec[1].encode("utf-8"))
        elif kind == "rows":
            with open(p, "w") as f:
                f.write(spec[1])
                f.write(spec[2] * spec[3])
        elif kind == "sparse":
            with open(p, "wb") as f:
                f.truncate(spec[1])
        elif kind == "fifo":
            os.mkfifo(p)
        elif kind == "dir":
            p.mkdir()


def cli_cases(T, D):
    """(name, argv after kiln, expect, names its message should hold). T: the T3 scene, D: a finished run's dir."""
    C = []
    add = lambda name, argv, expect, names: C.append((name, argv, expect, names))
    for v in ("1e-300", "5e-324", "nan", "-1", "0", "inf", "1e400", "x"):
        add("checkpoint_every_" + v, ["run", T, "--checkpoint-every", v, "--t-end", "0.001"], "refuse", ["--checkpoint-every"])
    for v in ("nan", "0", "-1", "1e-400", "inf", "1e"):
        add("dt_arg_" + v, ["check", T, "--dt", v], "refuse", ["--dt"])
    for v in ("nan", "0", "1e400", "-3"):
        add("t_end_arg_" + v, ["run", T, "--t-end", v], "refuse", ["--t-end"])
    add("integrator_typo_run", ["run", T, "--integrator", "velocity-verle", "--t-end", "0.001"], "refuse", ["--integrator"])
    add("integrator_typo_check", ["check", T, "--integrator", "erk44"], "refuse", ["--integrator"])
    add("integrator_empty", ["check", T, "--integrator", ""], "refuse", ["--integrator"])
    add("set_unknown_key", ["check", T, "--set", "outptu_interval=1"], "refuse", ["--set", "outptu_interval"])
    add("set_no_equals", ["check", T, "--set", "dt"], "refuse", ["--set"])
    add("set_bad_utf8", ["check", T, "--set", "name=t3\udcff"], "refuse", ["--set", "name"])
    add("set_index_beyond", ["check", T, "--set", "particles.99.fill.count=1"], "refuse", ["particles.99"])
    add("set_list_for_number", ["check", T, "--set", "materials.copper.density=[1,2]"], "refuse", ["density"])
    add("set_unclosed_list", ["check", T, "--set", "gravity=[0"], "refuse", ["gravity"])
    add("set_required_null", ["check", T, "--set", "dt=null"], "refuse", ["dt"])
    add("set_quoted_number", ["check", T, "--set", "dt='2e-6'"], "refuse", ["dt"])
    add("set_tag", ["check", T, "--set", "dt=!!str 2e-6"], "refuse", ["dt"])
    add("set_second_document", ["check", T, "--set", "dt=2e-6\n---\nx: 1"], "refuse", ["dt"])
    add("set_100kB_value", ["check", T, "--set", "integrator=" + "v" * 100000], "refuse", ["integrator"])
    add("set_stiffness_1e300", ["run", T, "--set", "materials.copper.stiffness=1e300", "--t-end", "0.0004"], "either", ["stiffness", "dt"])
    add("out_is_a_file", ["run", T, "--t-end", "0.0004", "--out", "/etc/hostname"], "refuse", ["/etc/hostname"])
    add("out_under_proc", ["run", T, "--t-end", "0.0004", "--out", "/proc/kiln_out"], "refuse", ["/proc/kiln_out"])
    add("scene_missing", ["check", "/nonexistent/scene.yaml"], "refuse", ["scene"])
    add("scene_directory", ["check", "/tmp"], "refuse", ["/tmp"])
    add("scene_dev_zero", ["check", "/dev/zero"], "refuse", ["/dev/zero"])
    add("scene_dev_urandom", ["check", "/dev/urandom"], "refuse", ["/dev/urandom"])
    add("restart_missing", ["run", "--restart", "/nonexistent/checkpoint.h5"], "refuse", ["checkpoint"])
    add("restart_dev_zero", ["run", "--restart", "/dev/zero"], "refuse", ["/dev/zero"])
    add("restart_a_yaml", ["run", "--restart", T], "refuse", ["t3_heap.yaml"])
    add("restart_a_result", ["run", "--restart", D + "/result.h5"], "refuse", ["result.h5"])
    add("restart_with_other_scene", ["run", "--restart", D + "/checkpoint.h5", str(REPO / "cases" / "t1_free_fall.yaml")], "refuse", ["scene"])
    add("restart_at_its_end", ["run", "--restart", D + "/checkpoint.h5"], "refuse", ["--t-end"])
    add("movie_missing_dir", ["movie", "/nonexistent/run"], "refuse", ["/nonexistent/run"])
    add("movie_empty_dir", ["movie", "@EMPTY"], "refuse", ["result.h5"])
    add("movie_fps_0", ["movie", D, "--fps", "0"], "refuse", ["--fps"])
    add("movie_fps_1e9", ["movie", D, "--fps", "1000000000"], "refuse", ["--fps"])
    add("movie_temperature_not_thermal", ["movie", D, "--field", "temperature"], "refuse", ["temperature"])
    add("plot_empty_dir", ["plot", "@EMPTY"], "refuse", ["summary.json"])
    add("order_bad_integrators", ["order", T, "--integrators", "erk4,nope", "--dt", "1e-6", "--levels", "2", "--t-end", "1e-4"], "refuse", ["nope"])
    add("order_dt_nan", ["order", T, "--integrators", "erk4", "--dt", "nan", "--levels", "2"], "refuse", ["--dt"])
    add("order_levels_1000", ["order", T, "--integrators", "erk4", "--dt", "1e-6", "--levels", "1000"], "refuse", ["--levels"])
    add("sweep_min_above_max", ["sweep", T, "--integrator", "erk4", "--dt-min", "1e-3", "--dt-max", "1e-6"], "refuse", ["--dt"])
    add("bench_columns_0", ["bench", "--columns", "0"], "refuse", ["--columns"])
    add("bench_columns_1e12", ["bench", "--columns", "1000000000000"], "refuse", ["--columns"])
    add("no_command", [], "refuse", ["subcommand"])
    add("unknown_command", ["frobnicate"], "refuse", ["frobnicate"])
    return C


def make_reference_run(kiln, d, t_end="0.004", extra=()):
    shutil.rmtree(d, ignore_errors=True)
    r = run_proc([kiln.bin, "run", str(REPO / "cases" / "t3_heap.yaml"), "--quiet", "--out", d, "--t-end", t_end,
                  "--set", "output_interval=0.001"] + list(extra), 300)
    if r["rc"] != 0:
        raise SystemExit("the reference run failed: %s" % r["stderr"][:500])
    return r


def checkpoint_edits():
    """(name, edit(h5py File)): changes a checkpoint after it was written; each must be refused (checksums)."""
    def flip_bits(f):
        a = f["real/state"][...]
        raw = a.view(numpy.uint64)
        for k, bit in ((3, 1), (40, 17), (77, 40), (301, 62)):
            raw[k] ^= numpy.uint64(1 << bit)
        f["real/state"][...] = a

    def scale(f):
        a = f["real/state"][...]
        a[0] *= 1e200
        f["real/state"][...] = a

    def shorten(name):
        def edit(f):
            a = f[name][...]
            del f[name]
            f.create_dataset(name, data=a[: max(0, len(a) // 2)])
        return edit

    def delete(name):
        def edit(f):
            del f[name]
        return edit

    def add(f):
        f.create_dataset("real/extra", data=numpy.zeros(3))

    def scene_text(f):
        a = f["text/scene.text"][...]
        s = bytes(a).replace(b"count: 300", b"count: 299")
        del f["text/scene.text"]
        f.create_dataset("text/scene.text", data=numpy.frombuffer(s, dtype=a.dtype))

    def version(f):
        a = f["text/kiln_version"][...]
        s = bytes(a).replace(b"0.1.0", b"0.0.9")
        del f["text/kiln_version"]
        f.create_dataset("text/kiln_version", data=numpy.frombuffer(s, dtype=a.dtype))
    return [("ckpt_flip_4_bits", flip_bits), ("ckpt_coordinate_x1e200", scale),
            ("ckpt_shorten_state", shorten("real/state")), ("ckpt_shorten_pairs_i", shorten("integer/system.pairs.i")),
            ("ckpt_shorten_slots", shorten("integer/system.particle_at_slot")), ("ckpt_delete_frames", delete("integer/frames")),
            ("ckpt_add_dataset", add), ("ckpt_edit_scene_text", scene_text), ("ckpt_other_version", version)]


def part_b(kiln, out, log):
    d = out / "inputs" / "handwritten"
    shutil.rmtree(d, ignore_errors=True)
    d.mkdir(parents=True)
    work = out / "work" / "b"
    work.mkdir(parents=True, exist_ok=True)
    records = []
    geo = d / "geometry"
    geo.symlink_to(REPO / "cases" / "geometry")

    def keep(rec):
        rec["part"] = "b"
        records.append(rec)
        log(rec)

    # 1. the fuzzers' regressions and corpus
    for sub_dir in ("regressions", "corpus/scene", "corpus/checkpoint"):
        for f in sorted((REPO / "tests" / "fuzz" / sub_dir).iterdir()):
            if not f.is_file():
                continue
            if sub_dir == "corpus/checkpoint" or f.name.startswith("checkpoint_"):
                if not kiln.driver:
                    continue
                r = run_proc([kiln.driver, "checkpoint", str(f)], 120)
                verdict = "hang" if r["timeout"] else "crash" if crashed(r) or r["rc"] != 0 else "ok"
                keep({"id": "fuzz/%s/%s" % (sub_dir, f.name), "kind": "checkpoint edit script", "file": str(f),
                      "check": slim(r), "verdict": verdict, "reasons": [] if verdict == "ok" else [r["stderr"][-300:]]})
                continue
            text = f.read_bytes().decode("utf-8", "surrogateescape")
            scene = d / ("fuzz_" + f.name)
            scene.write_bytes(f.read_bytes())
            expect = "accept" if sub_dir == "corpus/scene" else "either"
            rec = scene_case(kiln, str(scene), text, work, None, expect)
            rec.update({"id": "fuzz/%s/%s" % (sub_dir, f.name), "kind": "scene", "file": str(scene)})
            keep(rec)
    # 2. hand-written scenes (issue 28's list and more)
    for name, text, expect, files, extra in handwritten_scenes():
        sd = d / name
        sd.mkdir()
        materialise(files, sd)
        scene = sd / "scene.yaml"
        scene.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
        t = text.decode("latin-1") if isinstance(text, bytes) else text
        rec = scene_case(kiln, str(scene), t, work, None, expect, names=["scene.yaml"] + list(files), extra=extra)
        rec.update({"id": "hand/" + name, "kind": "scene", "expect": expect, "file": str(scene)})
        keep(rec)
        for name2, spec in files.items():  # large or special files: gone once judged
            if spec[0] in ("sparse", "rows", "fifo"):
                (sd / name2).unlink()
                (sd / (name2 + ".MADE_BY_SCRIPT")).write_text(repr(spec[:2] if spec[0] != "rows" else spec[:3] + (spec[3],)))
    # 3. command lines
    ref = work / "ref_run"
    make_reference_run(kiln, ref)
    empty = work / "empty"
    empty.mkdir(exist_ok=True)
    T = str(REPO / "cases" / "t3_heap.yaml")
    for name, argv, expect, names in cli_cases(T, str(ref)):
        argv = [str(empty) if a == "@EMPTY" else a for a in argv]
        out_dir = work / ("cli_" + name)
        shutil.rmtree(out_dir, ignore_errors=True)
        if argv and argv[0] == "run" and "--out" not in argv and "--restart" not in argv:
            argv = argv + ["--out", str(out_dir), "--quiet"]
        timeout = 120 if argv[:1] in (["order"], ["sweep"], ["movie"], ["bench"]) else 60
        r = run_proc([kiln.bin] + argv, timeout)
        shutil.rmtree(out_dir, ignore_errors=True)
        if r["timeout"]:
            verdict, why = "hang", ["ran past %d s" % timeout]
        elif crashed(r):
            verdict, why = "crash", ["exit %s signal %s: %s" % (r["rc"], r["signal"], r["stderr"][-300:])]
        elif r["rc"] == 0 and expect == "refuse":
            verdict, why = "wrong_accept", ["exit 0 where a refusal was due"]
        elif r["rc"] != 0:
            bad = message_quality(r, names)
            verdict, why = ("refused_poor_message", bad) if bad else ("refused", [])
        else:
            verdict, why = "ok", []
        keep({"id": "cli/" + name, "kind": "command line", "expect": expect, "check": slim(r), "verdict": verdict,
              "reasons": why})
    # 4. checkpoints changed after they were written (h5py): the checksums must refuse each
    if h5py is not None:
        for name, edit in checkpoint_edits():
            cd = work / ("ckpt_" + name)
            shutil.rmtree(cd, ignore_errors=True)
            shutil.copytree(ref, cd, ignore=shutil.ignore_patterns("previous", ".kiln.lock"))
            with h5py.File(cd / "checkpoint.h5", "r+") as f:
                edit(f)
            shutil.copy(cd / "checkpoint.h5", d / (name + ".h5"))
            r = run_proc([kiln.bin, "run", "--restart", cd / "checkpoint.h5", "--t-end", "0.006", "--quiet"], 60)
            if r["timeout"]:
                verdict, why = "hang", []
            elif crashed(r):
                verdict, why = "crash", [r["stderr"][-300:]]
            elif r["rc"] == 0:
                verdict, why = "wrong_accept", ["a changed checkpoint resumed with exit 0"]
            else:
                bad = message_quality(r, ["checkpoint.h5"])
                if r["rc"] != 2:
                    bad.append("exit %s, not 2" % r["rc"])
                verdict, why = ("refused_poor_message", bad) if bad else ("refused", [])
            keep({"id": "ckpt/" + name, "kind": "changed checkpoint", "expect": "refuse", "file": str(d / (name + ".h5")),
                  "check": slim(r), "verdict": verdict, "reasons": why})
            shutil.rmtree(cd, ignore_errors=True)
    # 5. commands on a run that is still running
    live = work / "live"
    shutil.rmtree(live, ignore_errors=True)
    p = subprocess.Popen([kiln.bin, "run", T, "--quiet", "--out", str(live), "--t-end", "0.2"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 30
    while not (live / "checkpoint.h5").exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.3)
    for name, argv, names in (("movie_on_running_run", ["movie", str(live)], ["running"]),
                              ("plot_on_running_run", ["plot", str(live)], ["summary.json", "running"]),
                              ("second_run_same_dir", ["run", T, "--quiet", "--out", str(live), "--t-end", "0.001"], ["lock", "running", "in use"]),
                              ("restart_of_running_run", ["run", "--restart", str(live / "checkpoint.h5"), "--quiet"], ["running", "lock", "in use"])):
        running = p.poll() is None
        r = run_proc([kiln.bin] + argv, 60)
        if r["timeout"]:
            verdict, why = "hang", []
        elif crashed(r):
            verdict, why = "crash", [r["stderr"][-300:]]
        elif r["rc"] == 0:
            verdict, why = "wrong_accept", ["exit 0 on a run still running"]
        else:
            bad = message_quality(r, names)
            verdict, why = ("refused_poor_message", bad) if bad else ("refused", [])
        keep({"id": "live/" + name, "kind": "command on a running run", "expect": "refuse", "check": slim(r),
              "verdict": verdict, "reasons": why, "run_was_running": running})
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    p.wait()
    shutil.rmtree(live, ignore_errors=True)
    return records


# ------------------------------------------------------------------------------------------------
# Parts c and d: kills, full and read-only disks

FRAME_SETS = ("time", "position", "velocity", "angle", "angular_velocity", "temperature", "wall_force", "wall_torque",
              "wall_power", "wall_segments")
SUMMARY_SKIP = {"wall_seconds", "run_id", "start_time", "resumed_at", "profile", "particle_steps_per_second",
                "estimate_seconds", "checkpoint"}


def frames_equal(a, b):
    """'' when the two results' frame datasets are the same bits, else what differs."""
    if h5py is None:
        return "no h5py"
    try:
        with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
            for name in FRAME_SETS:
                if (name in fa) != (name in fb):
                    return "dataset %s in one only" % name
                if name in fa:
                    x, y = fa[name][...], fb[name][...]
                    if x.shape != y.shape:
                        return "%s shape %s vs %s" % (name, x.shape, y.shape)
                    if x.tobytes() != y.tobytes():
                        return "%s differs" % name
    except Exception as e:  # noqa: BLE001
        return "unreadable: %s" % e
    return ""


def summary_diff(a, b, path=""):
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            if k in SUMMARY_SKIP:
                continue
            if k not in a or k not in b:
                out.append(path + k + " in one only")
            else:
                out += summary_diff(a[k], b[k], path + k + ".")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [path + " length"]
        return [d for x, y in zip(a, b) for d in summary_diff(x, y, path)]
    return [] if a == b or (a != a and b != b) else [path.rstrip(".")]


KILL_SCENE_SETS = ["output_interval=0.005"]
KILL_T_END = "0.2"
KILL_CHECKPOINT_EVERY = "0.02"


def kill_argv(kiln, d, t_end=KILL_T_END):
    argv = [kiln.bin, "run", str(REPO / "cases" / "t3_heap.yaml"), "--quiet", "--out", str(d), "--t-end", t_end,
            "--checkpoint-every", KILL_CHECKPOINT_EVERY]
    for s in KILL_SCENE_SETS:
        argv += ["--set", s]
    return argv


def start(argv, fsize=None):
    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (AS_LIMIT, AS_LIMIT))
        if fsize is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    env = dict(os.environ, OMP_NUM_THREADS="1")
    return subprocess.Popen([str(a) for a in argv], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            preexec_fn=limits, start_new_session=True)


def kill_when(p, cond, give_up):
    """Polls cond() and SIGKILLs p when it holds; returns the moment (s after start) or None if p ended first."""
    t0 = time.monotonic()
    while p.poll() is None:
        if cond(time.monotonic() - t0) or time.monotonic() - t0 > give_up:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
            return time.monotonic() - t0
        time.sleep(0.0005)
    return None


def listing(d):
    return sorted(x.name for x in Path(d).iterdir()) if Path(d).exists() else []


def resume_and_compare(kiln, d, ref, env_fsize=None):
    r = run_proc([kiln.bin, "run", "--restart", Path(d) / "checkpoint.h5", "--quiet"], 300, env_extra={"OMP_NUM_THREADS": "1"},
                 fsize=env_fsize)
    res = {"restart": slim(r)}
    if r["rc"] != 0:
        res["outcome"] = "refused" if r["rc"] in (1, 2) else "failed"
        return res
    diff = frames_equal(Path(ref) / "result.h5", Path(d) / "result.h5")
    try:
        sd = summary_diff(json.loads((Path(ref) / "summary.json").read_text()), json.loads((Path(d) / "summary.json").read_text()))
    except Exception as e:  # noqa: BLE001
        sd = ["summary unreadable: %s" % e]
    res["frames_diff"], res["summary_diff"] = diff, sd[:20]
    res["outcome"] = "identical" if not diff and not sd else "different"
    return res


def part_c(kiln, out, n_kills, seed, log):
    work = out / "work" / "c"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    ref = work / "reference"
    p = start(kill_argv(kiln, ref))
    t0 = time.monotonic()
    p.wait()
    wall = time.monotonic() - t0
    if p.returncode != 0:
        raise SystemExit("part c: the reference run failed: " + p.stderr.read().decode()[:500])
    p.stderr.close()
    rng = random.Random(seed + 28)
    plans = []
    fractions = [0.01, 0.03, 0.08, 0.15, 0.25, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85, 0.93]
    for f in fractions:
        plans.append(("at %.0f%% of the run's time" % (100 * f), "time", f * wall * rng.uniform(0.95, 1.05)))
    for k in (1, 3, 6):
        plans.append(("while writing checkpoint %d (checkpoint.h5.tmp present)" % k, "checkpoint", k))
    for name in ("result.xdmf.tmp", "picture.png.tmp", "summary.json.tmp", "result.h5+no summary"):
        plans.append(("during publication (%s)" % name, "publish", name))
    for f in (0.97, 0.99, 0.995):  # the last steps, the final checkpoint, the frame views, publication
        plans.append(("at %.1f%% of the run's time (its end)" % (100 * f), "time", f * wall))
    plans.append(("during the restart of a killed run, then restarted again", "restart", 0.5))
    plans.append(("during the restart of a killed run, then restarted again", "restart", 0.9))
    while len(plans) < n_kills:
        plans.append(("at a random moment", "time", rng.uniform(0.02, 0.98) * wall))
    if n_kills < len(plans):  # --quick or a smaller --kills: a spread of the plans
        plans = [plans[k * len(plans) // n_kills] for k in range(max(n_kills, 1))]
    records = []
    for i, (what, kind, arg) in enumerate(plans):
        for attempt in range(8 if kind == "publish" else 1):  # publication takes milliseconds: try again when missed
            d = work / ("kill%02d" % i)
            shutil.rmtree(d, ignore_errors=True)
            p = start(kill_argv(kiln, d))
            seen = {"n": 0, "was": False}

            def cond(t):
                if kind in ("time", "restart"):
                    return t >= (arg if kind == "time" else 0.5 * wall)
                if kind == "checkpoint":
                    now = (d / "checkpoint.h5.tmp").exists()
                    if now and not seen["was"]:
                        seen["n"] += 1
                    seen["was"] = now
                    return now and seen["n"] >= arg
                if arg == "result.h5+no summary":
                    return (d / "result.h5").exists() and not (d / "summary.json").exists()
                return (d / arg).exists()
            moment = kill_when(p, cond, 4 * wall + 30)
            p.stderr.close()
            rec = {"part": "c", "id": "kill%02d" % i, "what": what, "killed_at_s": None if moment is None else round(moment, 4),
                   "left": listing(d), "attempt": attempt + 1}
            if moment is None:
                if kind == "publish" and attempt < 7:
                    continue
                rec.update({"outcome": "not killed (the run ended first)", "verdict": "missed"})
                records.append(rec)
                log(rec)
                break
            rec["tmp_frames"] = frames_in(d / "result.h5.tmp") if (d / "result.h5.tmp").exists() else None
            if kind == "restart":  # kill the restart itself after arg of its time, then restart again
                q = start([kiln.bin, "run", "--restart", d / "checkpoint.h5", "--quiet"])
                time.sleep(arg * wall * 0.5)
                if q.poll() is None:
                    os.killpg(q.pid, signal.SIGKILL)
                    rec["restart_killed"] = True
                q.wait()
                q.stderr.close()
                rec["left_after_restart_kill"] = listing(d)
            if not (d / "checkpoint.h5").exists():
                rec.update({"outcome": "no checkpoint yet (killed before the start's checkpoint)", "verdict": "nothing to resume"})
            else:
                rec.update(resume_and_compare(kiln, d, ref))
                rec["verdict"] = {"identical": "resumed identical", "different": "resumed different"}.get(rec["outcome"], "work lost")
            records.append(rec)
            log(rec)
            shutil.rmtree(d, ignore_errors=True)
            break
    return records, wall


def try_mount(args):
    r = subprocess.run(["mount"] + args, capture_output=True, text=True)
    return r.returncode == 0, (r.stderr or r.stdout).strip()


def digest_dir(d):
    out = {}
    for p in sorted(Path(d).rglob("*")):
        if p.is_file():
            out[str(p.relative_to(d))] = hashlib.sha256(p.read_bytes()).hexdigest()[:16]
    return out


def judge_output_failure(r):
    """A failed output must be one clear message and an exit code of the table (4, or 2 when checked up front)."""
    if r["timeout"]:
        return "hang", ["ran past its bound"]
    if r["rc"] in (0, 2, 4) and r["signal"] == 0 and "Traceback" in r["stderr"]:
        return "failed, poor message", ["a Python traceback (%d lines)" % r["stderr"].count("\n")]
    if crashed(r):
        return "crash", ["exit %s signal %s: %s" % (r["rc"], r["signal"], r["stderr"][-300:])]
    if r["rc"] == 0:
        return "succeeded", []
    bad = []
    if r["rc"] not in (2, 4):
        bad.append("exit %s" % r["rc"])
    if r["stderr_len"] >= MESSAGE_BOUND or r["stderr"].count("\n") > 3:
        bad.append("%d lines, %d bytes" % (r["stderr"].count("\n"), r["stderr_len"]))
    if not r["stderr"].strip():
        bad.append("no message")
    return ("failed, poor message", bad) if bad else ("failed, clear message", [])


def run_with_limit_case(kiln, work, ref, label, limit=None, out_dir=None):
    d = Path(out_dir) if out_dir else work / label
    if not out_dir:
        shutil.rmtree(d, ignore_errors=True)
    r = run_proc(kill_argv(kiln, d, "0.1"), 300, fsize=limit, env_extra={"OMP_NUM_THREADS": "1"})
    rec = {"part": "d", "id": label, "limit": limit, "run": slim(r), "left": listing(d)}
    rec["verdict"], rec["reasons"] = judge_output_failure(r)
    if r["rc"] == 4:
        kept = frames_in(d / "result.h5.unfinished") if (d / "result.h5.unfinished").exists() else None
        rec["kept_frames"] = kept
        rec["kept_checkpoint"] = (d / "checkpoint.h5").exists()
        m = re.search(r"cannot write frame (\d+)", r["stderr"])
        rec["frames_finished_before"] = int(m.group(1)) if m else None
        lost = []
        if not rec["kept_checkpoint"] and (m is None or int(m.group(1)) > 0):
            lost.append("no checkpoint kept")
        if kept == -1:
            lost.append("result.h5.unfinished unreadable")
        rec["work_lost"] = lost
        return rec, d
    rec["work_lost"] = []
    return rec, d


def part_d(kiln, out, log, quick):
    work = out / "work" / "d"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    records = []

    def keep(rec):
        records.append(rec)
        log(rec)
    ref = work / "reference"
    r = run_proc(kill_argv(kiln, ref, "0.1"), 300, env_extra={"OMP_NUM_THREADS": "1"})
    if r["rc"] != 0:
        raise SystemExit("part d: the reference run failed: " + r["stderr"][:500])
    size = (ref / "result.h5").stat().st_size
    ck = (ref / "checkpoint.h5").stat().st_size
    limits = [16 << 10, ck // 2, ck + 4096, 3 * ck, size // 3, size // 2, size - (300 << 10), size - (100 << 10), size - 4096,
              size + (64 << 10)]
    if quick:
        limits = limits[::3]
    for limit in sorted(set(max(4096, x) for x in limits)):
        rec, d = run_with_limit_case(kiln, work, ref, "ulimit_f_%d" % limit, limit)
        rec["reference_size"] = size
        if rec["run"]["rc"] == 4 and rec.get("kept_checkpoint"):
            rec.update(resume_and_compare(kiln, d, ref))
            if rec.get("outcome") != "identical":
                rec["work_lost"].append("restart: " + rec.get("outcome", "?"))
        keep(rec)
        shutil.rmtree(d, ignore_errors=True)
    # A restart on a full disk keeps what it resumed from, and resumes again once there is room.
    d = work / "restart_full"
    p = start(kill_argv(kiln, d, "0.1"))
    kill_when(p, lambda t: (d / "result.h5.tmp").exists() and t > 0.5 * r["secs"], 60)
    p.stderr.close()
    if (d / "checkpoint.h5").exists():
        before = digest_dir(d)
        rr = run_proc([kiln.bin, "run", "--restart", d / "checkpoint.h5", "--quiet"], 120, fsize=size // 2)
        rec = {"part": "d", "id": "restart_on_full_disk", "run": slim(rr), "left": listing(d)}
        rec["verdict"], rec["reasons"] = judge_output_failure(rr)
        after = digest_dir(d)
        rec["kept_unchanged"] = all(after.get(k) == v for k, v in before.items() if k in ("checkpoint.h5",))
        rec["work_lost"] = [] if (d / "checkpoint.h5").exists() else ["checkpoint gone"]
        rec.update(resume_and_compare(kiln, d, ref))
        if rec.get("outcome") != "identical":
            rec["work_lost"].append("second restart: " + rec.get("outcome", "?"))
        keep(rec)
    shutil.rmtree(d, ignore_errors=True)
    # Full disk for the other writers: order, plot, movie (file-size limit)
    T = str(REPO / "cases" / "t3_heap.yaml")
    plot_dir = work / "plotted"
    shutil.copytree(ref, plot_dir, ignore=shutil.ignore_patterns(".kiln.lock", "previous"))
    T1 = str(REPO / "cases" / "t1_free_fall.yaml")
    others = [("order_full_disk_png", [kiln.bin, "order", T1, "--integrators", "erk2,erk4", "--dt", "1e-4", "--levels", "3",
                                       "--t-end", "0.01", "--quiet", "--out", work / "order_full"], 8 << 10, 300),
              ("order_full_disk_json", [kiln.bin, "order", T1, "--integrators", "erk2,erk4", "--dt", "1e-4", "--levels", "3",
                                        "--t-end", "0.01", "--quiet", "--out", work / "order_full1"], 1 << 10, 300),
              ("plot_full_disk", [kiln.bin, "plot", plot_dir, "--quiet"], 8 << 10, 120),
              ("movie_full_disk", [kiln.bin, "movie", plot_dir, "--quiet"], 8 << 10, 300)]
    for label, argv, limit, bound in others:
        before = digest_dir(plot_dir)
        rr = run_proc(argv, bound, fsize=limit)
        rec = {"part": "d", "id": label, "limit": limit, "run": slim(rr)}
        rec["verdict"], rec["reasons"] = judge_output_failure(rr)
        after = digest_dir(plot_dir)
        rec["work_lost"] = ["%s changed or gone" % k for k, v in before.items() if after.get(k) != v]
        keep(rec)
    # A small tmpfs: a disk that is really full
    mnt = work / "tmpfs"
    mnt.mkdir()
    ok, why = try_mount(["-t", "tmpfs", "-o", "size=%dk" % max(64, size // 2048), "kiln_campaign", str(mnt)])
    if ok:
        try:
            rec, d = run_with_limit_case(kiln, work, ref, "tmpfs_half_the_result", None, mnt / "run")
            rec["tmpfs_size"] = size // 2
            if rec["run"]["rc"] == 4:
                moved = work / "tmpfs_moved"
                shutil.copytree(mnt / "run", moved)
                rec.update(resume_and_compare(kiln, moved, ref))
                if rec.get("outcome") != "identical":
                    rec["work_lost"].append("restart elsewhere: " + rec.get("outcome", "?"))
                shutil.rmtree(moved, ignore_errors=True)
            keep(rec)
        finally:
            subprocess.run(["umount", str(mnt)])
    else:
        keep({"part": "d", "id": "tmpfs", "verdict": "not measured", "reasons": ["mount -t tmpfs refused: " + why]})
    # Read-only output directories: a read-only bind mount if mount works, else chattr +i
    ro = work / "readonly"
    ro.mkdir()
    shutil.copytree(ref, ro / "finished", ignore=shutil.ignore_patterns(".kiln.lock", "previous"))
    (ro / "empty").mkdir()
    method = None
    ok, why = try_mount(["--bind", str(ro), str(ro)])
    if ok:
        ok2, why2 = try_mount(["-o", "remount,bind,ro", str(ro)])
        if ok2:
            method = "read-only bind mount"
        else:
            subprocess.run(["umount", str(ro)])
            why = why2
    if method is None:
        c = subprocess.run(["chattr", "+i", str(ro), str(ro / "finished"), str(ro / "empty")], capture_output=True, text=True)
        method = "chattr +i" if c.returncode == 0 else None
        why += "; chattr: " + c.stderr.strip()
    if method is None:
        keep({"part": "d", "id": "readonly", "verdict": "not measured", "reasons": [why]})
    else:
        before = digest_dir(ro / "finished")
        cases = [("run_into_readonly", [kiln.bin, "run", T, "--t-end", "0.0004", "--quiet", "--out", ro / "empty" / "new"]),
                 ("run_into_readonly_existing", [kiln.bin, "run", T, "--t-end", "0.0004", "--quiet", "--out", ro / "empty"]),
                 ("order_into_readonly", [kiln.bin, "order", str(REPO / "cases" / "t1_free_fall.yaml"), "--integrators",
                                          "erk2,erk4", "--dt", "1e-4", "--levels", "3", "--t-end", "0.01", "--quiet",
                                          "--out", ro / "empty" / "order"]),
                 ("plot_readonly_run", [kiln.bin, "plot", ro / "finished", "--quiet"]),
                 ("movie_readonly_run", [kiln.bin, "movie", ro / "finished", "--quiet"]),
                 ("restart_readonly_run", [kiln.bin, "run", "--restart", ro / "finished" / "checkpoint.h5", "--t-end", "0.12", "--quiet"])]
        for label, argv in cases:
            rr = run_proc(argv, 300)
            rec = {"part": "d", "id": label, "method": method, "run": slim(rr)}
            rec["verdict"], rec["reasons"] = judge_output_failure(rr)
            if rr["rc"] == 0:
                rec["verdict"], rec["reasons"] = "wrong_accept", ["exit 0 writing into a read-only directory"]
            after = digest_dir(ro / "finished")
            rec["work_lost"] = ["%s changed or gone" % k for k, v in before.items() if after.get(k) != v]
            keep(rec)
        if method == "chattr +i":
            subprocess.run(["chattr", "-i", str(ro), str(ro / "finished"), str(ro / "empty")])
        else:
            subprocess.run(["umount", str(ro)])
    return records


# ------------------------------------------------------------------------------------------------
# Part e (not in the default parts): what the hardening costs a normal run, this binary against
# --old-kiln (one built from a commit before issue 28's fixes), alternated, medians

def big_lattice_scene(d, rows, columns):
    text = sub(t3(), "    radius: {uniform: [0.001, 0.002]}\n    fill: {rectangle: [-0.025, 0.005, 0.025, 0.125], count: 300, seed: 3}\n",
               "    radius: 0.0004\n    lattice: {kind: hexagonal, origin: [-0.11, 0.001], spacing: 0.001, rows: %d, columns: %d}\n" % (rows, columns))
    text = text.replace("[[-0.12, 0.15], [-0.12, 0.0], [0.12, 0.0], [0.12, 0.15]]", "[[-0.12, 10.0], [-0.12, 0.0], [0.12, 0.0], [0.12, 10.0]]")
    path = Path(d) / ("lattice_%dx%d.yaml" % (rows, columns))
    path.write_text(text)
    return path


def part_e(new, old, out, reps, log):
    work = out / "work" / "e"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    T = str(REPO / "cases" / "t3_heap.yaml")
    big = big_lattice_scene(work, 1000, 200)  # 200,000 discs on a floor
    ckdir = {}

    def t3_full(k, d):
        return [k, "run", T, "--quiet", "--profile", "--out", d]

    def t3_ckpt(k, d):
        return [k, "run", T, "--quiet", "--profile", "--out", d, "--t-end", "0.2", "--checkpoint-every", "0.002"]

    def t3_plain(k, d):
        return [k, "run", T, "--quiet", "--profile", "--out", d, "--t-end", "0.2"]

    def t3_frames(k, d):
        return [k, "run", T, "--quiet", "--profile", "--out", d, "--t-end", "0.02", "--set", "output_interval=2e-6"]

    def t3_few_frames(k, d):
        return [k, "run", T, "--quiet", "--profile", "--out", d, "--t-end", "0.02"]

    def restart(k, d):  # goes on from a 0.2 s run's checkpoint for 100 steps (a fresh copy each time)
        return None

    def big_run(k, d):  # the start check, 2 steps and two checkpoints of 200,000 discs
        return [k, "run", big, "--quiet", "--profile", "--out", d, "--set", "dt=1e-6", "--t-end", "2e-6"]

    def big_restart(k, d):  # reads that run's checkpoint, 2 steps more
        return None

    def check_small(k, d):
        return [k, "check", T]

    def check_big(k, d):
        return [k, "check", big]
    measures = [("T3 whole run (the main command)", t3_full, 1), ("T3 0.2 s, default checkpoints", t3_plain, 1),
                ("T3 0.2 s, a checkpoint every 0.002 s (100)", t3_ckpt, 1), ("T3 0.02 s, 11 frames", t3_few_frames, 1),
                ("T3 0.02 s, a frame every step (10,001)", t3_frames, 1), ("restart from a T3 checkpoint (one step)", restart, 5),
                ("kiln check T3", check_small, 10), ("kiln check, 200,000 discs on a lattice", check_big, 1),
                ("run of 200,000 discs: start check, 2 steps, 2 checkpoints", big_run, 1),
                ("restart of 200,000 discs from its checkpoint, 2 steps", big_restart, 1)]
    sources = {restart: ([T, "--t-end", "0.2"], "0.2002"), big_restart: ([big, "--set", "dt=1e-6", "--t-end", "2e-6"], "4e-6")}
    rows = []
    for name, make, inner in measures:
        times = {"old": [], "new": []}
        stages = {"old": [], "new": []}
        for rep in range(reps):
            order = (("old", old), ("new", new)) if rep % 2 == 0 else (("new", new), ("old", old))
            for label, binary in order:
                d = work / ("%s_%d" % (label, len(rows)))
                if make in sources and (binary, name) not in ckdir:
                    cd = work / ("ck_%s_%d" % (label, len(rows)))
                    shutil.rmtree(cd, ignore_errors=True)
                    r = run_proc([binary, "run"] + sources[make][0] + ["--quiet", "--out", cd], 600)
                    ckdir[(binary, name)] = cd
                for _ in range(inner):
                    shutil.rmtree(d, ignore_errors=True)
                    if make in sources:  # a fresh copy of the run each time
                        shutil.rmtree(work / "rs", ignore_errors=True)
                        shutil.copytree(ckdir[(binary, name)], work / "rs", ignore=shutil.ignore_patterns(".kiln.lock", "previous"))
                        argv = [binary, "run", "--restart", work / "rs" / "checkpoint.h5", "--t-end", sources[make][1], "--quiet"]
                    else:
                        argv = make(binary, d)
                    r = run_proc(argv, 1800)
                    if r["rc"] not in (0, 1):
                        log({"part": "e", "id": name, "verdict": "failed", "reasons": [label, r["stderr"][:300]]})
                    times[label].append(r["secs"])
                    try:
                        summ = json.loads((d / "summary.json").read_text())
                        prof = dict(summ["profile"]["seconds"])
                        prof["wall_seconds"] = summ.get("wall_seconds")
                        stages[label].append(prof)
                    except Exception:  # noqa: BLE001
                        pass
                shutil.rmtree(d, ignore_errors=True)
        med = {k: sorted(v)[len(v) // 2] if v else None for k, v in times.items()}
        row = {"measure": name, "runs_each": len(times["new"]), "old_median_s": med["old"], "new_median_s": med["new"],
               "old_s": times["old"], "new_s": times["new"],
               "change": None if not med["old"] else round(med["new"] / med["old"] - 1, 4)}
        for label in ("old", "new"):
            if stages[label] and isinstance(stages[label][0], dict):
                keys = stages[label][0].keys()
                row[label + "_profile_median"] = {k: sorted(p.get(k) or 0 for p in stages[label])[len(stages[label]) // 2]
                                                  for k in keys}
        rows.append(row)
        log({"part": "e", "id": name, "verdict": "measured", "reasons": ["old %s s, new %s s" % (med["old"], med["new"])]})
    return rows


# ------------------------------------------------------------------------------------------------
# Summary

def summarise(records, meta):
    a = [r for r in records if r.get("part") == "a"]
    b = [r for r in records if r.get("part") == "b"]
    c = [r for r in records if r.get("part") == "c"]
    d = [r for r in records if r.get("part") == "d"]
    count = lambda rs, v: sum(1 for r in rs if r.get("verdict") == v)
    rows = []
    for name, rs in (("a mutated scenes", a), ("b hand-written inputs", b)):
        rows.append({"part": name, "inputs": len(rs), "crash": count(rs, "crash"), "hang": count(rs, "hang"),
                     "wrong_accept": count(rs, "wrong_accept"), "wrong_refusal": count(rs, "wrong_refusal"),
                     "refused": count(rs, "refused"), "refused_poor_message": count(rs, "refused_poor_message"),
                     "ok": count(rs, "ok") + count(rs, "accepted")})
    kills = {"kills": len([r for r in c if r.get("verdict") != "missed"]), "missed": count(c, "missed"),
             "resumed_identical": count(c, "resumed identical"), "resumed_different": count(c, "resumed different"),
             "work_lost": count(c, "work lost"), "nothing_to_resume": count(c, "nothing to resume")}
    disks = {"cases": len(d), "clear_message": count(d, "failed, clear message"), "poor_message": count(d, "failed, poor message"),
             "crash": count(d, "crash"), "hang": count(d, "hang"), "succeeded": count(d, "succeeded"),
             "wrong_accept": count(d, "wrong_accept"), "not_measured": count(d, "not measured"),
             "work_lost": sum(1 for r in d if r.get("work_lost"))}
    return {"meta": meta, "scenes": rows, "kills": kills, "disks": disks}


def table(s):
    lines = ["| part | inputs | crash | hang | wrong accept | wrong refusal | refused | refused, poor message | accepted, ran |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in s["scenes"]:
        lines.append("| %s | %d | %d | %d | %d | %d | %d | %d | %d |" % (r["part"], r["inputs"], r["crash"], r["hang"],
                     r["wrong_accept"], r["wrong_refusal"], r["refused"], r["refused_poor_message"], r["ok"]))
    k = s["kills"]
    lines += ["", "| c kills | killed | resumed, identical | resumed, different | work lost (refused or failed) | nothing to resume yet | run ended first |",
              "|---|---|---|---|---|---|---|",
              "| T3 | %d | %d | %d | %d | %d | %d |" % (k["kills"], k["resumed_identical"], k["resumed_different"], k["work_lost"],
                                                    k["nothing_to_resume"], k["missed"])]
    d = s["disks"]
    lines += ["", "| d disks | cases | failed, clear message | failed, poor message | crash | hang | succeeded | wrong accept | work lost | not measured |",
              "|---|---|---|---|---|---|---|---|---|---|",
              "| full, read-only | %d | %d | %d | %d | %d | %d | %d | %d | %d |" % (d["cases"], d["clear_message"], d["poor_message"],
                                                                             d["crash"], d["hang"], d["succeeded"], d["wrong_accept"],
                                                                             d["work_lost"], d["not_measured"])]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kiln", default=str(REPO / "build" / "kiln"))
    ap.add_argument("--driver", default=str(REPO / "build" / "fuzz_driver"), help="tests/fuzz/fuzz_driver (structural mutations, checkpoint edit scripts)")
    ap.add_argument("--out", default="/tmp/campaign")
    ap.add_argument("--quick", action="store_true", help="a small campaign to check the script (60 scenes, 4 kills)")
    ap.add_argument("--parts", default="abcd")
    ap.add_argument("--mutated", type=int, default=None, help="mutated scenes (default 2200, quick 60)")
    ap.add_argument("--kills", type=int, default=None, help="kills: the 24 planned moments, and random ones up to this many (quick: 4)")
    ap.add_argument("--seed", type=int, default=28)
    ap.add_argument("--old-kiln", default=None, help="part e: a kiln built before the hardening, timed against --kiln")
    ap.add_argument("--reps", type=int, default=3, help="part e: runs of each binary per measure (alternated)")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # The binaries are copied: a rebuild during the campaign does not change what is measured.
    bin_dir = out / "bin"
    bin_dir.mkdir(exist_ok=True)
    shutil.copy2(args.kiln, bin_dir / "kiln")
    driver = None
    if Path(args.driver).exists():
        shutil.copy2(args.driver, bin_dir / "fuzz_driver")
        driver = bin_dir / "fuzz_driver"
    kiln = Kiln(bin_dir / "kiln", driver)
    n_mutated = args.mutated if args.mutated is not None else (60 if args.quick else 2200)
    n_kills = args.kills if args.kills is not None else (4 if args.quick else 24)
    head = subprocess.run(["git", "-C", str(REPO), "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    meta = {"date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "git_head": head, "kiln_sha256": hashlib.sha256(
        (bin_dir / "kiln").read_bytes()).hexdigest()[:16], "quick": args.quick, "seed": args.seed, "mutated": n_mutated,
        "kills": n_kills, "pyyaml": getattr(yaml, "__version__", None), "h5py": getattr(h5py, "__version__", None) if h5py else None,
        "fuzz_driver": bool(driver), "nproc": os.cpu_count(), "timeouts_s": {"check": CHECK_TIMEOUT, "run": RUN_TIMEOUT},
        "short_run_steps": SHORT_STEPS}
    records = []
    results_path = out / "results.json"
    t_start = time.monotonic()
    done = {"n": 0}

    def log(rec):
        done["n"] += 1
        v = rec.get("verdict")
        if v not in ("ok", "refused", "accepted", "resumed identical", "failed, clear message") or done["n"] % 100 == 0:
            print("[%6.0f s] %-4s %-45s %s %s" % (time.monotonic() - t_start, rec.get("part"), str(rec.get("id"))[:45], v,
                                               "; ".join(rec.get("reasons", []))[:160]), flush=True)
    timing = {}
    if "a" in args.parts:
        t = time.monotonic()
        records += part_a(kiln, out, n_mutated, args.seed, log)
        timing["a"] = time.monotonic() - t
        results_path.write_text(json.dumps({"meta": meta, "records": records}, indent=1, default=str))
    if "b" in args.parts:
        t = time.monotonic()
        records += part_b(kiln, out, log)
        timing["b"] = time.monotonic() - t
        results_path.write_text(json.dumps({"meta": meta, "records": records}, indent=1, default=str))
    if "c" in args.parts:
        t = time.monotonic()
        recs, wall = part_c(kiln, out, n_kills, args.seed, log)
        meta["kill_reference_wall_s"] = round(wall, 2)
        records += recs
        timing["c"] = time.monotonic() - t
    if "d" in args.parts:
        t = time.monotonic()
        records += part_d(kiln, out, log, args.quick)
        timing["d"] = time.monotonic() - t
    if "e" in args.parts:
        if not args.old_kiln:
            raise SystemExit("part e needs --old-kiln")
        shutil.copy2(args.old_kiln, bin_dir / "kiln_old")
        t = time.monotonic()
        costs = part_e(str(bin_dir / "kiln"), str(bin_dir / "kiln_old"), out, args.reps, log)
        timing["e"] = time.monotonic() - t
        (out / "costs.json").write_text(json.dumps(costs, indent=1))
        print("\n| measure | runs each | before (s, median) | now (s, median) | change |\n|---|---|---|---|---|")
        for row in costs:
            print("| %s | %d | %s | %s | %s |" % (row["measure"], row["runs_each"], row["old_median_s"], row["new_median_s"],
                                             "" if row["change"] is None else "%+.1f %%" % (100 * row["change"])))
    meta["seconds_per_part"] = {k: round(v, 1) for k, v in timing.items()}
    meta["children_cpu_s"] = round(resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime +
                                   resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime, 1)
    results_path.write_text(json.dumps({"meta": meta, "records": records}, indent=1, default=str))
    s = summarise(records, meta)
    (out / "summary.json").write_text(json.dumps(s, indent=1))
    text = table(s)
    (out / "summary.md").write_text(text + "\n")
    print()
    print(text)
    print("\nresults: %s (%d records); %s" % (results_path, len(records), json.dumps(meta["seconds_per_part"])))
    if LOADER is None:
        print("PyYAML missing: the YAML oracle (Y1-Y4) was skipped")
    if h5py is None:
        print("h5py missing: frame counts and bit-for-bit comparisons were skipped")


if __name__ == "__main__":
    main()
