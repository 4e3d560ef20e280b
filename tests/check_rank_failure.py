#!/usr/bin/env python3
"""A launch of several ranks where one rank fails alone ends promptly, with that rank's message:

    python3 tests/check_rank_failure.py GAPFE MPIEXEC WORK

The ranks of a partitioned run fail together on what they all see (a bad deck, a step Newton cannot take);
these are the failures only one rank meets (docs/cluster.md "When a rank fails"). Without a word between
the ranks, the others would wait for the failed one in their next collective call: before the listening
thread, two minutes, then an abort that did not say why. On 2 ranks unless said:

  * rank 1 cannot read its deck (an MPMD launch gives it a missing file): rank 0, which read the deck and
    went on to the partitioned run, ends the launch and prints rank 1's message; on 3 ranks too, where rank
    2 leaves the ending to rank 0;
  * rank 0 cannot read its deck: it prints its own message and the launch ends;
  * rank 1 is given an output folder that is not there: it cannot open its part's files, and every rank
    fails with its message;
  * the output folder is taken away in the middle of a run (replaced by a file): no rank can write its part
    of the next increment (each writes its own, docs/cluster.md "Output"), and every rank fails with the
    lowest one's message (the writes are agreed);
  * failures every rank meets (no rank can read the deck, with and without the listening thread; a bad
    option; several ranks without solver = petsc) still print one line and end normally.

Each must end within LIMIT seconds (the listener's grace is 0.5 s, 2 s on ranks other than 0; the limit
allows a busy machine and MPI's start-up), with the exit status of the failure (3: a file), and the one line
gapfe prints for it must appear once (mpirun adds its own lines about the abort). A launch that does not end
is killed with its processes and counts as a failure. Exit status 0 when all pass (tests/checks.py)."""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.dont_write_bytecode = True
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "bench"))
import deckgen  # noqa: E402
from checks import check, finish  # noqa: E402

LIMIT = 8.0  # seconds for the launch, MPI's start included (the listener's grace is 0.5-2 s)


def launch(cmd, env):
    """Starts `cmd` in a process group of its own, so that a launch that hangs can be ended whole."""
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)


def ended(process, cmd, timeout):
    """The launch's outcome, or a CompletedProcess with return code None when it had to be killed."""
    try:
        stdout, stderr = process.communicate(timeout=timeout)
        return subprocess.CompletedProcess(cmd, process.returncode, stdout, stderr)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        stdout, stderr = process.communicate()
        return subprocess.CompletedProcess(cmd, None, stdout, stderr)


def gapfe_lines(text):
    return [line for line in text.splitlines() if line.startswith("gapfe")]


def check_launch(name, done, seconds, expected_code, needles):
    """The launch's outcome against what it should be (tests/checks.py's tally)."""
    lines = gapfe_lines(done.stderr)
    print(f"{name}: exit {done.returncode} after {seconds:.1f} s; gapfe said: {lines}")
    check(done.returncode == expected_code, f"{name}: exit status {done.returncode}, expected {expected_code}")
    check(seconds <= LIMIT, f"{name}: ended {seconds:.1f} s after the failure, more than {LIMIT} s")
    check(len(lines) == 1 and all(n in lines[0] for n in needles),
          f"{name}: expected one gapfe line naming {needles}, got {lines}")


def main():
    gapfe, mpiexec, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")
    # A plastic tube of 200 steps: room to fail in the middle, and a large model (grid points times steps past
    # app::kLargeModel), which re-executes itself for huge pages: before MPI starts, never after.
    deck = os.path.join(work, "plastic.deck")
    with open(deck, "w") as f:
        f.write(deckgen.plastic_tube_deck(ni=61, steps=200))
    missing = os.path.join(work, "missing.deck")
    run = ["run", "--solver", "petsc", "--plot", "none", "--quiet"]

    # One rank's deck cannot be read (MPMD: each rank its own command line).
    for bad, ranks in ((1, 2), (0, 2), (1, 3)):
        decks = [deck] * ranks
        decks[bad] = missing
        cmd = [mpiexec]
        for rank in range(ranks):
            cmd += (["-np", "1", gapfe, run[0], decks[rank], "--out", os.path.join(work, f"out_{bad}")] + run[1:] +
                    ([":"] if rank < ranks - 1 else []))
        start = time.monotonic()
        done = ended(launch(cmd, env), cmd, 120)
        check_launch(f"rank {bad} of {ranks} cannot read its deck", done, time.monotonic() - start, 3,
                          ["gapfe: rank 1: ", "missing.deck"] if bad == 1 else ["gapfe: cannot", "missing.deck"])

    # Rank 1 is given a folder that is not there (as on a node that does not share rank 0's): it cannot open
    # its part's files, and every rank fails with its message (opening them is agreed).
    cmd = [mpiexec, "-np", "1", gapfe, run[0], deck, "--out", os.path.join(work, "out_shared")] + run[1:] + \
          [":", "-np", "1", gapfe, run[0], deck, "--out", os.path.join(work, "nowhere", "out")] + run[1:]
    start = time.monotonic()
    done = ended(launch(cmd, env), cmd, 120)
    check_launch("rank 1's folder is not there", done, time.monotonic() - start, 3,
                 ["gapfe: ", "nowhere/out/nodes_p1.csv"])

    # Failures every rank meets stay one line: a deck no rank can read (with and without the listening
    # thread), a bad option, a launch of several ranks without solver = petsc.
    out_all = os.path.join(work, "out_all")
    for name, args, code, needles, more in [
            ("no rank can read its deck", ["run", missing, "--out", out_all] + run[1:], 3,
             ["gapfe: cannot", "missing.deck"], {}),
            ("no rank can read its deck, no listener", ["run", missing, "--out", out_all] + run[1:], 3,
             ["gapfe: cannot", "missing.deck"], {"GAPFE_RANK_LISTENER": "0"}),
            ("a bad option on every rank", ["run", deck, "--out", out_all, "--bogus"], 64, ["gapfe: ", "--bogus"], {}),
            ("several ranks without PETSc", ["run", deck, "--out", out_all, "--quiet"], 1, ["gapfe: ", "petsc"], {})]:
        start = time.monotonic()
        cmd = [mpiexec, "-np", "2", gapfe] + args
        done = ended(launch(cmd, dict(env, **more)), cmd, 120)
        check_launch(name, done, time.monotonic() - start, code, needles)

    # The output folder replaced by a file in the middle of the run.
    out = os.path.join(work, "out_mid")
    cmd = [mpiexec, "-np", "2", gapfe, run[0], deck, "--out", out] + run[1:]
    running = launch(cmd, env)
    deadline = time.monotonic() + 120
    while not os.path.exists(os.path.join(out, "step_0002.pvtu")) and running.poll() is None:
        if time.monotonic() > deadline:
            break
        time.sleep(0.02)
    if running.poll() is not None or time.monotonic() > deadline:
        done = ended(running, cmd, 1)
        check(False, f"the run ended (exit {done.returncode}) before its folder could be taken away")
    else:
        os.rename(out, out + ".taken")
        with open(out, "w") as f:
            f.write("not a folder\n")
        start = time.monotonic()
        done = ended(running, cmd, 120)
        check_launch("the output folder taken away", done, time.monotonic() - start, 3, ["out_mid"])
        # What the folder kept lists only whole increments: every .pvtu result.pvd names, and every piece of it.
        taken = out + ".taken"

        def text(name):
            with open(os.path.join(taken, name)) as f:
                return f.read()

        pvd = os.path.exists(os.path.join(taken, "result.pvd"))
        listed = re.findall(r'file="([^"]+)"', text("result.pvd")) if pvd else []
        missing = [f for f in listed if not os.path.exists(os.path.join(taken, f))]
        for f in set(listed) - set(missing):
            missing += [p for p in re.findall(r'Source="([^"]+)"', text(f))
                        if not os.path.exists(os.path.join(taken, p))]
        print(f"the folder taken away: result.pvd lists {len(listed)} increment(s); missing files: {missing}")
        check(listed, "the folder taken away: no result.pvd, or one that lists nothing")
        check(not missing, f"result.pvd of the folder taken away lists missing files {missing}")

    finish("rank failures: ")


if __name__ == "__main__":
    main()
