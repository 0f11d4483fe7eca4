"""Running decks with epaphe-run: finding the executable, the cases of a study (deck text, output,
log, status), checking their decks before anything runs, running them several at a time with a
progress line (count of cases done, ETA)."""
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor, wait
from typing import Optional

from .errors import EpapheError
from .results import Run
from .study import StudyError

# epaphe-run's progress line: "... 12.71 s left ...", "2 min 05 s left", "1 h 02 min left", "765.22 ms left"
LEFT = re.compile(r"(?:(\d+) h (\d+) min|(\d+) min (\d+) s|([0-9.]+) (s|ms|us)) left")


def seconds_left(line):
    """The time left that an epaphe-run progress line states, in s (None when it states none)."""
    m = LEFT.search(line)
    if not m:
        return None
    h, hm, m_, ms, x, unit = m.groups()
    if h is not None:
        return 3600.0 * int(h) + 60.0 * int(hm)
    if m_ is not None:
        return 60.0 * int(m_) + int(ms)
    return float(x) * {"s": 1.0, "ms": 1e-3, "us": 1e-6}[unit]


SOURCE_BUILD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "drivers")


_SAY = threading.Lock()


def say(msg):
    """One line on stdout, whole (the cases of a study print from several threads)."""
    with _SAY:
        sys.stdout.write(msg + "\n")
        sys.stdout.flush()


def find_run(given: Optional[str] = None) -> str:
    """The epaphe-run to use.

    Parameters
    ----------
    given : str, optional
        An executable to use (checked).

    Returns
    -------
    str
        `given`, else the first of: next to the running command (an install's bin/),
        $EPAPHE_BUILD_DIR/drivers, the source tree's build/drivers, PATH.

    Raises
    ------
    StudyError
        `given` is not an executable file, or no epaphe-run is found.
    """
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)):
            raise StudyError(f"--run {given}: not an executable file")
        return os.path.abspath(given)
    cands = [os.path.join(os.path.dirname(os.path.abspath(sys.argv[0] or ".")), "epaphe-run")]
    bd = os.environ.get("EPAPHE_BUILD_DIR")
    if bd:
        cands.append(os.path.join(bd, "drivers", "epaphe-run"))
    cands.append(SOURCE_BUILD + "/epaphe-run")
    for c in cands:
        if os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.abspath(c)
    w = shutil.which("epaphe-run")
    if w:
        return w
    raise StudyError(
        "epaphe-run not found next to this script, in $EPAPHE_BUILD_DIR/drivers or build/drivers, "
        "nor on PATH: give it with --run"
    )


class Case:
    """One run of a study: its name, legend label, overrides, deck text and files in `rundir`."""

    def __init__(self, name, label, overrides, deck_text, rundir):
        self.name, self.label, self.overrides, self.deck_text = name, label, overrides, deck_text
        self.xml = os.path.join(rundir, name + ".xml")
        self.h5 = os.path.join(rundir, name + ".h5")
        self.log = os.path.join(rundir, name + ".log")
        self.status = "not run"
        self.cached = False
        self.hist = None
        self.measures, self.errors, self.ref = {}, {}, None
        self.is_reference = False
        self.alone = False  # a reference run that is not one of the study's variants

    def cached_ok(self):
        if not os.path.isfile(self.h5):
            return False
        try:
            with Run(self.h5) as run:
                return run.complete and run.deck_text == self.deck_text
        except (OSError, EpapheError):
            return False


def default_jobs(threads):
    """Cases run at a time when --jobs is not given: the cores this process may use
    (os.sched_getaffinity: a taskset or a container's limit counts) divided by the threads of each
    run, at least 1; threads 0 (each run takes every core) gives 1."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    return max(1, cores // threads) if threads > 0 else 1


def check_decks(runs, run_exe, study_where, jobs=1):
    """epaphe-run --check on every variant deck before anything runs, `jobs` at a time; the first
    refused deck in study order is the error."""
    todo = [r for r in runs if not r.cached_ok()]  # the others: this very deck text ran to completion
    for r in todo:
        with open(r.xml, "w") as fh:
            fh.write(r.deck_text)

    def check(r):
        return subprocess.run([run_exe, "--check", r.xml], capture_output=True, text=True)

    with ThreadPoolExecutor(max_workers=max(1, min(jobs, len(todo) or 1))) as pool:
        checked = list(pool.map(check, todo))
    for r, proc in zip(todo, checked):
        if proc.returncode != 0:
            msg = (proc.stderr.strip() or proc.stdout.strip()).splitlines()
            msg = msg[0] if msg else f"exit status {proc.returncode}"
            msg = msg.replace("epaphe-run: error: ", "")
            over = ", ".join(f"'{k}' = '{v}'" for k, v in r.overrides.items()) or "no override"
            where = next((wh for k, wh in r.wheres.items() if f"'Epaphe->{k}'" in msg), study_where)
            raise StudyError(f"{where}: run '{r.name}' ({over}): epaphe-run refuses the deck: {msg}")


def clock(seconds):
    """0:37, 12:05, 1:02:03."""
    s = int(round(max(seconds, 0.0)))
    h, m, s = s // 3600, s // 60 % 60, s % 60
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class Progress:
    """The cases finished out of `total`, and the time left. The mean time of a case is that of the
    cases that ran to completion (before the first, of every case that ran; never the cached ones,
    which take no time). A running case has left what its epaphe-run last said ("... 3.2 s left" on
    its progress line), else the mean less the time it has run; a case still waiting, the mean.
    ETA: that work shared by the `jobs` running at a time, and no less than the longest running
    case's time left."""

    def __init__(self, total, jobs, to_run):
        self.total, self.jobs = total, jobs
        self.done = 0
        self.waiting = to_run  # cases to run (not cached) not started yet
        self.running = {}  # case name -> start time (time.monotonic)
        self.said_left = {}  # case name -> (time.monotonic, s left) from its progress line
        self.complete_secs, self.other_secs = [], []
        self.stopping = False
        self.lock = threading.Lock()

    def start(self, r):
        with self.lock:
            self.waiting -= 1
            self.running[r.name] = time.monotonic()

    def update(self, r, seconds_left):
        with self.lock:
            self.said_left[r.name] = (time.monotonic(), seconds_left)

    def finish(self, r, secs, line):
        """Counts `r` done (`secs`: its time, None when cached) and prints `line`; the count and
        ETA after it."""
        with self.lock:
            self.done += 1
            if secs is not None:
                self.running.pop(r.name, None)
                self.said_left.pop(r.name, None)
                if r.status == "complete":
                    self.complete_secs.append(secs)
                elif not r.status.startswith("stopped"):  # a stopped run's time says nothing
                    self.other_secs.append(secs)
            say(f"{line}; {self.summary()}")

    def summary(self):
        left = self.total - self.done
        text = f"{self.done} of {self.total} done, {left} left"
        if self.stopping:
            return text + ", interrupted: no other case starts"
        timed = self.complete_secs or self.other_secs
        if not timed:
            return text + (", ETA unknown (no case timed yet)" if left else "")
        mean = sum(timed) / len(timed)
        now = time.monotonic()
        running_left = []
        for name, t0 in self.running.items():
            if name in self.said_left:
                when, left_then = self.said_left[name]
                running_left.append(max(left_then - (now - when), 0.0))
            else:
                running_left.append(max(mean - (now - t0), 0.0))
        work = sum(running_left) + mean * self.waiting
        at_once = min(self.jobs, len(self.running) + self.waiting)
        eta = max(work / at_once if at_once else 0.0, max(running_left, default=0.0))
        return text + f", ETA {clock(eta)} (mean {mean:.1f} s a case, {self.jobs} at a time)"


class CaseRunner:
    """Runs the cases of a study with epaphe-run, `jobs` processes at a time (threads of a pool,
    each waiting on one epaphe-run), the cases started in study order. Each case prints
    "[i/N] NAME: running (LABEL)", epaphe-run's progress lines (prefixed with "[i/N] NAME:" when
    several run at once), and a line when it ends with its status, its time, the count of cases
    done and the ETA (Progress). A case that fails does not stop the others. The runs are started
    in a session of their own: a Ctrl-C reaches this process only, which passes one SIGINT to every
    running epaphe-run (each stops at the end of its step with a checkpoint and the status
    "stopped: interrupted by SIGINT"), starts no other case, waits for them and raises
    KeyboardInterrupt; a second Ctrl-C while waiting kills them."""

    def __init__(self, run_exe, threads, jobs, force):
        self.run_exe, self.threads, self.jobs, self.force = run_exe, threads, max(1, jobs), force
        self.lock = threading.Lock()
        self.procs = {}  # case name -> running epaphe-run (Popen)
        self.stopping = False
        self.env = dict(os.environ)
        if self.jobs > 1:
            # bound threads (OMP_PROC_BIND=true/close) of several runs would all take the first cores
            self.env["OMP_PROC_BIND"] = "false"

    def run(self, cases):
        total = len(cases)
        fresh = [self.force or not r.cached_ok() for r in cases]
        self.progress = Progress(total, min(self.jobs, max(1, sum(fresh))), sum(fresh))
        pool = ThreadPoolExecutor(max_workers=self.jobs)
        futures = []
        try:
            try:
                for i, (r, f) in enumerate(zip(cases, fresh), 1):
                    futures.append(pool.submit(self.case, r, i, total, not f))
                while wait(futures, timeout=0.5).not_done:  # a timeout: Ctrl-C is seen here
                    pass
            except KeyboardInterrupt:
                self.stop(signal.SIGINT)
                try:
                    wait(futures)
                except KeyboardInterrupt:
                    self.stop(signal.SIGKILL)
                    wait(futures)
                stopped = [r.name for r in cases if r.status.startswith("stopped: interrupted by")]
                say(
                    f"interrupted: {self.progress.done} of {total} case(s) done"
                    + (f"; stopped {', '.join(stopped)} (each history ends with a checkpoint)" if stopped else "")
                )
                raise
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
        for f in futures:
            f.result()  # an error of this script (not of a run) in a worker

    def stop(self, sig):
        self.progress.stopping = True
        with self.lock:
            self.stopping = True
            for p in self.procs.values():
                if p.poll() is None:
                    p.send_signal(sig)

    def case(self, r, index, total, cached):
        head = f"[{index}/{total}] {r.name}"
        if cached:
            r.cached, r.status = True, "complete"
            self.progress.finish(r, None, f"{head}: cached ({os.path.relpath(r.h5)})")
            return
        with self.lock:
            if self.stopping:
                r.status = "not run: interrupted"
                return
        if os.path.exists(r.h5):
            os.remove(r.h5)
        say(f"{head}: running ({r.label})")
        tag = f"    {head}: " if self.jobs > 1 else "    "
        cmd = [self.run_exe, os.path.basename(r.xml), "--threads", str(self.threads)]
        self.progress.start(r)
        start = time.time()
        proc, err, rc = None, "", None
        with open(r.log, "w") as log:
            with self.lock:
                if not self.stopping:
                    try:
                        proc = subprocess.Popen(
                            cmd,
                            cwd=os.path.dirname(r.xml),
                            stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE,
                            text=True,
                            env=self.env,
                            start_new_session=True,
                        )
                        self.procs[r.name] = proc
                    except OSError as e:  # the executable went away (a rebuild), no memory, ...
                        err = f"cannot start {self.run_exe}: {e.strerror or e}"
                        log.write(err + "\n")
            if proc is not None:
                for line in proc.stdout:
                    log.write(line)
                    if line.startswith("  t = "):  # epaphe-run's progress line
                        say(tag + line.strip())
                        left = seconds_left(line)
                        if left is not None:
                            self.progress.update(r, left)
                err = proc.stderr.read()
                log.write(err)
                rc = proc.wait()
                with self.lock:
                    del self.procs[r.name]
        secs = time.time() - start
        status = None
        if os.path.isfile(r.h5):
            try:
                with Run(r.h5) as run:
                    status = run.status
            except (OSError, EpapheError):
                status = None
        first = err.strip().replace("epaphe-run: error: ", "").splitlines()
        first = first[0] if first else f"exit status {rc}"
        if rc == 0 and status == "complete":
            r.status = "complete"
        elif "exceeds the critical step" in err:
            m = re.search(r"exceeds the critical step ([0-9.eE+-]+) s", err)
            r.status = "refused: unstable time step" + (f" (critical {float(m.group(1)):.3g} s)" if m else "")
        elif status and status.startswith("stopped"):
            r.status = status
        elif self.stopping and not err:  # a signal before the time loop: nothing to keep
            r.status = "stopped: interrupted " + ("before it started" if proc is None else "during its setup")
        else:
            r.status = "failed: " + first
        self.progress.finish(
            r,
            secs,
            f"{head}: {r.status} in {secs:.1f} s"
            + ("" if r.status == "complete" else f" (log: {os.path.relpath(r.log)})"),
        )
