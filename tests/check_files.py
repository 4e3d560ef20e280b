#!/usr/bin/python3
"""Files a user can trust, through the `gapfe` command (ctest `gapfe_files`): every input below is small and
written here, every refusal is checked for its exit code and for a message that names the place.

  * Hostile inputs, one per class: a Gmsh file (made by Gmsh: tests/data/make_two_groups.py) that puts the
    surface in two physical groups, in MSH 2.2 (each cell written twice) and 4.1, solved against Lame's
    thick tube; two materials on one cell; a curve named twice, or two curves sharing edges, in one
    [[load]]; repeated cells and corners, repeated group names, tags past 2^31 and empty names in
    hand-written MSH files; a temperature point too far to interpolate (deck card and scene key); a grid of
    2e8 points holding one cell (memory follows the cell); /dev/zero, a FIFO and a folder named as a mesh or
    a deck; a large deck on standard input.
  * Output folders: a second run into a used folder leaves only its own files; a folder holding results no
    run wrote is refused unless --overwrite; a planted symbolic link is replaced, its target untouched;
    a folder that cannot be made exits 3; `gapfe plot` refuses a folder without a manifest and a
    collection that points outside its folder, and says when a run did not complete.
  * Control characters and bytes that are not UTF-8 in a title: shown as \\xNN on the terminal, in the CSV
    tables and in every SVG picture, which parses as XML.
  * A run killed (SIGTERM, SIGKILL) at several moments: the folder reads back with meshio, Python's XML and
    CSV readers and `gapfe plot` (the project's own readers): the collection whole, every file it lists
    there, every CSV row whole.
  * PETSc (when the command has it): a petscrc in the working folder is not read; -options_file reads it.

    /usr/bin/python3 tests/check_files.py build/release/examples/gapfe WORKDIR
"""
import csv
import os
import pathlib
import resource
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import meshio

gapfe = str(pathlib.Path(sys.argv[1]).resolve())
work = pathlib.Path(sys.argv[2]).resolve()
root = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(root / "bench"))
import deckgen as g  # noqa: E402
from checks import check, finish  # noqa: E402  (tests/checks.py: the shared tally)



def gapfe_run(*args, cwd=None, stdin=None, timeout=120):
    p = subprocess.run([gapfe, *map(str, args)], cwd=cwd or work, input=stdin, capture_output=True,
                       timeout=timeout)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def refused(args, code, *needles, cwd=None, stdin=b""):
    """`gapfe ARGS` exits `code` with one line on stderr holding every needle (standard input empty)."""
    rc, _, err = gapfe_run(*args, cwd=cwd, stdin=stdin, timeout=30)
    line = err.strip()
    label = " ".join(map(str, args))
    check(rc == code, f"{label}: exit {rc}, expected {code} ({line})")
    check(line.count("\n") == 0, f"{label}: one line, got {line!r}")
    for n in needles:
        check(n in line, f"{label}: the message names {n!r}: {line!r}")
    return line


def fresh(name):
    d = work / name
    shutil.rmtree(d, ignore_errors=True)
    d.mkdir(parents=True)
    return d


def lame_bore(p=100.0, a=100.0, b=200.0, E=200000.0, nu=0.3):
    """u_r at the bore of a thick tube under internal pressure p, plane strain (Lame)."""
    return (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * a + b * b / a)


STEEL = "E = 200000.0\nnu = 0.3\nG = 76923.077\n"


def scene(mesh, materials, loads="[[load]]\ncurves = \"bore\"\npressure = 100.0\n", extra=""):
    return (f'title = "two groups"\n[mesh]\nfile = "{mesh}"\n{materials}'
            f'[[boundary]]\ngroups = ["bottom", "top"]\nfix = ["z"]\n{loads}{extra}')


# ---- a surface and a curve each in two physical groups, in Gmsh's own MSH 2.2 and 4.1
def two_groups():
    d = fresh("two_groups")
    for v in ("v22", "v41"):
        shutil.copy(root / "tests/data/scenes" / f"two_groups_{v}.msh", d)
        mesh = f"two_groups_{v}.msh"
        (d / f"both_{v}.toml").write_text(scene(mesh, f'[materials.steel]\nsurfaces = ["steel", "all"]\n{STEEL}'))
        rc, _, err = gapfe_run("run", d / f"both_{v}.toml", "--out", d / f"out_{v}", "--quiet")
        check(rc == 0, f"two groups {v}: runs ({err.strip()})")
        if rc == 0:
            rows = list(csv.DictReader(open(d / f"out_{v}" / "nodes.csv")))
            bore = [float(r["u_r"]) for r in rows if float(r["r"]) == 100.0]
            exact = lame_bore()
            # 8 x 2 quadrangles: 0.04 % from Lame; a cell assembled twice would give half.
            check(all(abs(u / exact - 1) < 2e-3 for u in bore),
                  f"two groups {v}: bore u_r {bore} within 0.2 % of Lame's {exact}")
        (d / f"two_{v}.toml").write_text(scene(
            mesh, f'[materials.steel]\nsurfaces = ["steel"]\n{STEEL}[materials.soft]\nsurfaces = ["all"]\n'
                  'E = 2000.0\nnu = 0.3\nG = 769.23077\n'))
        refused(["run", d / f"two_{v}.toml", "--out", d / "x"], 1, "materials.steel.surfaces", "(line ",
                "is also in \"all\" of [materials.soft]")
        for curves, needle in [('["bore", "inner"]', 'the curves "bore" and "inner" share'),
                               ('["bore", "bore"]', 'the curve "bore" is listed twice')]:
            (d / f"load_{v}.toml").write_text(scene(
                mesh, f'[materials.steel]\nsurfaces = ["steel"]\n{STEEL}',
                f"[[load]]\ncurves = {curves}\npressure = 100.0\n"))
            refused(["run", d / f"load_{v}.toml", "--out", d / "x"], 1, "load[1].curves", "(line 13)", needle)
    # Saved with Mesh.SaveAll = 1, MSH 2.2 loses every element's physical tag: the message says so.
    shutil.copy(root / "tests/data/scenes/two_groups_v22_saveall.msh", d)
    (d / "saveall.toml").write_text(scene("two_groups_v22_saveall.msh",
                                          f'[materials.steel]\nsurfaces = ["steel"]\n{STEEL}'))
    refused(["run", d / "saveall.toml", "--out", d / "x"], 1, "materials.steel.surfaces",
            'the surface group "steel" has no cells', "Mesh.SaveAll = 1")


# ---- two [[boundary]] tables meeting at a corner: each sets only its own directions there
def boundary_corner():
    d = fresh("corner")
    shutil.copy(root / "tests/data/scenes/two_groups_v41.msh", d)
    u = 0.05
    (d / "corner.toml").write_text(scene("two_groups_v41.msh", f'[materials.steel]\nsurfaces = ["steel"]\n{STEEL}',
                                         f"[[boundary]]\ngroups = [\"bore\"]\ndisplacement = {{r = {u}}}\n"))
    rc, _, err = gapfe_run("run", d / "corner.toml", "--out", d / "out", "--quiet")
    check(rc == 0, f"corner: runs ({err.strip()})")
    if rc != 0:
        return
    rows = list(csv.DictReader(open(d / "out" / "nodes.csv")))
    bore = [r for r in rows if float(r["r"]) == 100.0]
    zs = [float(r["z"]) for r in bore]
    corners = [r for r in bore if float(r["z"]) in (min(zs), max(zs))]
    check(len(corners) == 2, f"corner: two bore corners, got {len(corners)}")
    for r in corners:
        check(float(r["u_z"]) == 0.0, f"corner z = {r['z']}: fixed u_z kept beside the bore's u_r, got {r['u_z']}")
        check(abs(float(r["u_r"]) - u) < 1e-12, f"corner z = {r['z']}: u_r = {u} prescribed, got {r['u_r']}")
    # Lame's u_r = A r + B / r with a free outside falls from the bore outward and stays positive.
    outer = [float(r["u_r"]) for r in rows if float(r["r"]) == 200.0]
    check(all(0 < v < u for v in outer), f"corner: outer u_r between 0 and {u}: {outer}")


# ---- hand-written MSH files: each malformed class refused, naming the mesh's line
MSH_HEAD = ("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 3 \"bore\"\n2 1 \"steel\"\n"
            "1 4 \"ends\"\n$EndPhysicalNames\n$Nodes\n4\n1 100 0 0\n2 200 0 0\n3 200 10 0\n4 100 10 0\n"
            "$EndNodes\n")
MSH_CELLS = "$Elements\n4\n1 3 2 1 7 1 2 3 4\n2 1 2 3 5 4 1\n3 1 2 4 6 1 2\n4 1 2 4 6 3 4\n$EndElements\n"


def malformed_meshes():
    d = fresh("malformed")
    materials = f"[materials.steel]\nsurfaces = [\"steel\"]\n{STEEL}"
    body = (f'[mesh]\nfile = "m.msh"\n{materials}[[boundary]]\ngroups = ["ends"]\nfix = ["z"]\n'
            '[[load]]\ncurves = "bore"\npressure = 100.0\n')
    (d / "s.toml").write_text(body)
    (d / "m.msh").write_text(MSH_HEAD + MSH_CELLS)
    rc, _, err = gapfe_run("run", d / "s.toml", "--out", d / "ok", "--quiet")
    check(rc == 0, f"the hand-written mesh runs ({err.strip()})")
    cases = [
        (MSH_CELLS.replace("4\n1 3 2 1 7", "5\n5 3 2 1 7 1 2 3 4\n1 3 2 1 7"),
         "line 20 ($Elements): the element repeats the one of line 19 (the same nodes, in the same physical group)"),
        (MSH_CELLS.replace("1 3 2 1 7 1 2 3 4", "1 3 2 1 7 1 2 3 3"), "line 19 ($Elements): the element names node 3 twice"),
        (MSH_CELLS.replace("1 3 2 1 7", "1 3 2 4294967297 7"), "line 19 ($Elements): an element's physical tag"),
        (MSH_CELLS.replace("1 3 2 1 7 1 2", "1 3 2 1 7 \"\" 2"), "line 19 ($Elements): a quoted word"),
    ]
    for cells, needle in cases:
        (d / "m.msh").write_text(MSH_HEAD + cells)
        refused(["run", d / "s.toml", "--out", d / "x"], 1, "m.msh", needle)
    for names, needle in [('1 3 "bore"\n2 1 "steel"\n1 4 "bore"', 'physical groups 3 and 4 of dimension 1 are both named "bore"'),
                          ('1 3 "bore"\n2 1 ""\n1 4 "ends"', "line 7 ($PhysicalNames): an empty name")]:
        (d / "m.msh").write_text(MSH_HEAD.replace('1 3 "bore"\n2 1 "steel"\n1 4 "ends"', names) + MSH_CELLS)
        refused(["run", d / "s.toml", "--out", d / "x"], 1, "m.msh", needle)


# ---- a temperature point too far to interpolate; a grid far larger than what it holds
def one_cell_deck(extra_control=None, temperature=None, maxi=2, maxj=2):
    lines = ["$ format = elastic", "ONE CELL",
             g.control(numtc=1 if temperature else 0, numpc=1, **(extra_control or {})),
             g.mesh_control(maxi, maxj, 4, 1, 1),
             g.segment([(1, 1, 100.0, 0.0), (2, 1, 101.0, 0.0)], 1), g.segment([(2, 1, 101.0, 0.0), (2, 2, 101.0, 1.0)], 1),
             g.segment([(2, 2, 101.0, 1.0), (1, 2, 100.0, 1.0)], 1), g.segment([(1, 2, 100.0, 1.0), (1, 1, 100.0, 0.0)], 1),
             g.bc(1, 2, 2, 2, 2), g.block(1, 1, 2, 1, 2)]
    if temperature:
        lines.append(g.f(temperature[0], 10) + g.f(temperature[1], 10) + g.f(temperature[2], 10))
    lines += g.material(1, [g.isotropic(200000.0, 0.3, 1.2e-5)], elastic_format=True)
    lines.append(g.edge(1, 2, 100.0))  # the bottom edge, the cell on its left
    return "\n".join(lines) + "\n"


def far_and_large():
    d = fresh("far_and_large")
    (d / "far.deck").write_text(one_cell_deck(temperature=(1e200, 0.0, 100.0)))
    refused(["run", d / "far.deck", "--out", d / "x"], 1, "DATA NO. 9, temperature card 1 (r = 1e+200",
            "too far from it to interpolate")
    (d / "m.msh").write_text(MSH_HEAD + MSH_CELLS)
    (d / "far.toml").write_text(f'[mesh]\nfile = "m.msh"\n[materials.steel]\nsurfaces = ["steel"]\n{STEEL}'
                                '[temperature]\nreference = 0.0\npoints = [[1e200, 0.0, 50.0], [-1e200, 0.0, 10.0]]\n')
    refused(["run", d / "far.toml", "--out", d / "x"], 1, "temperature.points", "(line ", "too far")
    # One cell placed on a 99,999 x 2,000 grid (2e8 points): memory follows the cell, not the grid.
    (d / "large.deck").write_text(one_cell_deck(maxi=99999, maxj=2000))
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    rc, _, err = gapfe_run("run", d / "large.deck", "--out", d / "large", "--quiet", "--plot", "none")
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss  # KiB, the largest child so far
    check(rc == 0, f"a one-cell deck on a 99,999 x 2,000 grid runs ({err.strip()})")
    check(peak < 200_000 or before >= 200_000, f"a one-cell deck on a huge grid peaks at {peak} KiB (< 200 MB)")


# ---- only regular files are read; standard input at any size
def special_files():
    d = fresh("special")
    (d / "m.msh").write_text(MSH_HEAD + MSH_CELLS)
    fifo = d / "fifo.msh"
    os.mkfifo(fifo)
    for mesh, kind in [("/dev/zero", "is a device"), (str(fifo), "is a FIFO"), (str(d), "is a folder")]:
        (d / "s.toml").write_text(f'[mesh]\nfile = "{mesh}"\n[materials.steel]\n{STEEL}')
        refused(["run", d / "s.toml", "--out", d / "x"], 3, f"the mesh '{mesh}' {kind}")
        refused(["run", mesh, "--out", d / "x"], 3, f"the deck '{mesh}' {kind}")
    # A deck large enough that the command would re-execute itself (include/gapfe/app/command.hpp, kLargeModel),
    # piped in: read once, never again.
    deck = g.tube_deck(151, 151)
    rc, _, err = gapfe_run("run", "-", "--out", d / "stdin", "--quiet", "--plot", "none", stdin=deck.encode())
    check(rc == 0, f"a 151 x 151 deck on standard input runs ({err.strip()})")
    (d / "tube.deck").write_text(deck)
    rc, _, err = gapfe_run("run", d / "tube.deck", "--out", d / "file", "--quiet", "--plot", "none")
    check(rc == 0 and (d / "stdin/nodes.csv").read_bytes() == (d / "file/nodes.csv").read_bytes(),
          "the deck from standard input gives the file's results")
    refused(["run", "-", "--out", d / "x"], 1, "standard input", "the deck ends")


# ---- one run per output folder
def output_folders():
    d = fresh("folders")
    long_deck = one_cell_deck(extra_control={"nlinc": 5})
    (d / "long.deck").write_text(long_deck)
    (d / "short.deck").write_text(one_cell_deck(extra_control={"nlinc": 2}))
    out = d / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    rc, _, _ = gapfe_run("run", d / "long.deck", "--out", out, "--quiet")
    check(rc == 0 and (out / "step_0005.vtu").exists(), "the first run writes five steps")
    rc, _, _ = gapfe_run("plot", out, "--x", "load_factor", "--y", "u_max", "--quiet", "--no-png")
    check(rc == 0 and (out / "curve_u_max_load_factor.svg").exists(), "gapfe plot draws the first run's curve")
    rc, _, _ = gapfe_run("run", d / "short.deck", "--out", out, "--quiet")
    names = sorted(p.name for p in out.iterdir())
    check(rc == 0, "the second run into the used folder runs")
    check(not any(n in names for n in ("step_0003.vtu", "step_0005.vtu", "curve_u_max_load_factor.svg")),
          f"the second run leaves none of the first's files: {names}")
    check("notes.txt" in names and (out / "notes.txt").read_text() == "mine", "a user's file is kept")
    history = list(csv.DictReader(open(out / "history.csv")))
    check([r["step"] for r in history] == ["1", "2"], "history.csv holds the second run's two steps")
    pvd = [x.get("file") for x in ET.parse(out / "result.pvd").getroot().iter("DataSet")]
    check(pvd == ["step_0001.vtu", "step_0002.vtu"], f"result.pvd lists the second run's files: {pvd}")
    manifest = (out / "gapfe-run.txt").read_text()
    check("short.deck" in manifest and "status: complete" in manifest, f"the manifest names the run: {manifest!r}")
    # A folder with results no gapfe run wrote (an older gapfe, another program): refused, then --overwrite.
    other = d / "other"
    other.mkdir()
    (other / "history.csv").write_text("somebody else's\n")
    refused(["run", d / "short.deck", "--out", other], 3, f"the output folder '{other}' holds results",
            "history.csv", "--overwrite")
    check((other / "history.csv").read_text() == "somebody else's\n", "the refused folder is untouched")
    rc, _, _ = gapfe_run("run", d / "short.deck", "--out", other, "--quiet", "--overwrite")
    check(rc == 0 and (other / "history.csv").read_text().startswith("step,"), "--overwrite replaces them")
    # A run refused before it starts (a PETSc option without the PETSc solver) leaves the last run's files.
    refused(["run", d / "short.deck", "--out", other, "-ksp_type", "cg"], 1, "needs solver = petsc")
    check((other / "history.csv").exists() and "status: complete" in (other / "gapfe-run.txt").read_text(),
          "a refused run leaves the last run's files and manifest")
    # A planted link: replaced, never written through.
    target = d / "precious.txt"
    target.write_text("precious")
    for name in ("nodes.csv", "step_0001.vtu", "result.pvd", "deformed.svg"):
        (out / name).unlink()
        (out / name).symlink_to(target)
    rc, _, _ = gapfe_run("run", d / "short.deck", "--out", out, "--quiet")
    check(rc == 0 and target.read_text() == "precious", "planted links: the target is untouched")
    check(not any((out / n).is_symlink() for n in ("nodes.csv", "step_0001.vtu", "result.pvd")), "the links are gone")
    # A folder that cannot be made; an output file's name taken by a folder: exit 3, not 1.
    refused(["run", d / "short.deck", "--out", d / "short.deck" / "sub"], 3, "cannot make the output folder")
    blocked = fresh("folders_blocked")
    (blocked / "gapfe-run.txt").write_text("gapfe: this folder holds the files of one run: x\nstatus: complete\n")
    (blocked / "nodes.csv").mkdir()
    (blocked / "nodes.csv" / "keep").write_text("x")
    refused(["run", d / "short.deck", "--out", blocked], 3, "nodes.csv")
    # gapfe plot reads only a run's folder, and only the files beside it.
    refused(["plot", d], 3, "holds no gapfe-run.txt")
    (out / "result.pvd").write_text('<?xml version="1.0"?>\n<VTKFile type="Collection"><Collection>'
                                   '<DataSet timestep="1" file="../precious.txt"/></Collection></VTKFile>\n')
    refused(["plot", out], 3, "result.pvd lists '../precious.txt'")
    # A partitioned run's parallel file: its pieces are held to the same rule.
    (out / "result.pvd").write_text('<?xml version="1.0"?>\n<VTKFile type="Collection"><Collection>'
                                   '<DataSet timestep="1" file="step_0001.pvtu"/></Collection></VTKFile>\n')
    (out / "step_0001.pvtu").write_text('<?xml version="1.0"?>\n<VTKFile type="PUnstructuredGrid">'
                                       '<PUnstructuredGrid><Piece Source="../precious.txt"/></PUnstructuredGrid>'
                                       '</VTKFile>\n')
    refused(["plot", out], 3, "step_0001.pvtu lists '../precious.txt'")


# ---- control characters and bytes that are not UTF-8 in a title
def hostile_title():
    d = fresh("title")
    deck = (root / "examples/decks/thick_tube.deck").read_bytes().split(b"\n")
    deck[1] = b"\x1b[31mRED\x07 TUBE \xff\xfe <&> \x01 end"
    (d / "t.deck").write_bytes(b"\n".join(deck))
    p = subprocess.run([gapfe, "run", d / "t.deck", "--out", d / "out"], capture_output=True)
    check(p.returncode == 0, "a run with a hostile title")
    check(b"\x1b" not in p.stdout + p.stderr and b"\xff" not in p.stdout + p.stderr,
          "the terminal never sees the raw bytes")
    check(b"deck: \\x1b[31mRED\\x07 TUBE \\xff\\xfe <&> \\x01 end" in p.stdout, "the log shows them as \\xNN")
    svgs = sorted((d / "out").glob("*.svg"))
    check(len(svgs) >= 2, "pictures drawn")
    for svg in svgs:
        try:
            titles = [t.text for t in ET.parse(svg).getroot().iter("{http://www.w3.org/2000/svg}text")
                      if t.get("class") == "title"]
            check(any("\\x1b[31mRED\\x07 TUBE \\xff\\xfe <&> \\x01 end" in (t or "") for t in titles),
                  f"{svg.name}: the title shown with \\xNN")
        except ET.ParseError as e:
            check(False, f"{svg.name} parses as XML: {e}")


# ---- a run killed at any moment leaves a folder that reads back
def read_back(out, label):
    if not (out / "gapfe-run.txt").exists():  # killed before the folder was made ready: nothing to read
        check(not any(out.glob("*.csv")) if out.exists() else True, f"{label}: no tables without a manifest")
        return
    manifest = (out / "gapfe-run.txt").read_text()
    check("status: " in manifest, f"{label}: the manifest has a status")
    for table in ("nodes.csv", "elements.csv", "reactions.csv", "history.csv"):
        if not (out / table).exists():
            continue
        # Every row's width; the numbers of the first and last 500 rows (a kill tears at most the row being
        # written, the last; parsing each of a killed run's millions of rows took a minute of CI).
        lines = (out / table).read_text().splitlines()
        if lines:
            width = lines[0].count(",")
            torn = next((k for k, line in enumerate(lines, 1) if line.count(",") != width), None)
            check(torn is None, f"{label}: {table} row {torn} of {len(lines)} is whole")
            for r in csv.reader(lines[1:501] + lines[max(501, len(lines) - 500):]):
                if not all(number(x) for x in r):
                    check(False, f"{label}: {table}'s rows hold numbers only, not {r}")
                    break
    pvd = out / "result.pvd"
    if pvd.exists():
        try:
            files = [x.get("file") for x in ET.parse(pvd).getroot().iter("DataSet")]
        except ET.ParseError as e:
            check(False, f"{label}: result.pvd parses: {e}")
            return
        check(all((out / f).is_file() for f in files), f"{label}: every file result.pvd lists is there")
        for f in files[:1] + files[-3:]:  # meshio on the first and the last ones (the others alike)
            try:
                mesh = meshio.read(out / f)
                check(len(mesh.points) > 0 and "displacement" in mesh.point_data, f"{label}: {f} reads in meshio")
            except Exception as e:  # noqa: BLE001 - any reader failure is the finding
                check(False, f"{label}: {f} reads in meshio: {e}")
        if files:
            rc, _, err = gapfe_run("plot", out, "--quiet", "--no-png")
            check(rc == 0, f"{label}: gapfe plot reads it ({err.strip()})")
            check("did not complete" in err or "status: complete" in manifest,
                  f"{label}: gapfe plot says the run did not complete")
    if (out / "history.csv").exists() and len((out / "history.csv").read_text().splitlines()) > 1:
        rc, _, err = gapfe_run("plot", out, "--x", "load_factor", "--y", "u_max", "--quiet", "--no-png")
        check(rc == 0, f"{label}: gapfe plot reads history.csv ({err.strip()})")


def number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def killed_runs():
    d = fresh("killed")
    deck = g.tube_deck(31, 31).split("\n")
    deck[2] = g.control(numpc=30, nlinc=3000)  # 3000 steps, every increment written
    (d / "tube.deck").write_text("\n".join(deck))
    for k, (sig, after) in enumerate([(signal.SIGTERM, 0.3), (signal.SIGKILL, 0.5), (signal.SIGTERM, 1.1),
                                      (signal.SIGKILL, 1.7), (signal.SIGKILL, 2.3)]):
        out = d / f"run_{k}"
        p = subprocess.Popen([gapfe, "run", d / "tube.deck", "--out", out, "--quiet"], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        time.sleep(after)
        p.send_signal(sig)
        p.wait()
        label = f"killed by {sig.name} after {after} s"
        check(p.returncode != 0, f"{label}: the run was still going (make the deck longer)")
        read_back(out, label)


# ---- PETSc reads no option file it was not given
def petsc_options():
    d = fresh("petsc")
    (d / "t.deck").write_bytes((root / "examples/decks/thick_tube.deck").read_bytes())
    leak = d / "leak.txt"
    (d / "petscrc").write_text(f"-log_view :{leak}\n")
    (d / ".petscrc").write_text(f"-log_view :{leak}\n")
    rc, _, err = gapfe_run("run", "t.deck", "--out", "out", "--quiet", "--solver", "petsc", cwd=d)
    if "built without PETSc" in err:
        print("(this gapfe has no PETSc: the option-file check is skipped)")
        return
    check(rc == 0, f"a PETSc run beside a petscrc ({err.strip()})")
    check(not leak.exists(), "PETSc read no petscrc of the working folder")
    rc, _, err = gapfe_run("run", "t.deck", "--out", "out", "--quiet", "--solver", "petsc", "-options_file",
                           "petscrc", cwd=d)
    check(rc == 0 and leak.exists(), f"-options_file names one, and it is read ({err.strip()})")


for case in (two_groups, boundary_corner, malformed_meshes, far_and_large, special_files, output_folders, hostile_title,
             killed_runs, petsc_options):
    case()
finish()
