"""What the MPI tests share: a shipped example's deck made runnable from a work folder, the
mpirun launcher and its environment, and the last increment's ParaView fields of a run's output
folder (from its .vtu, or from the pieces its .pvtu joins, one per rank), keyed so that one
rank's file and N ranks' pieces compare entry by entry."""
import glob
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys


def read_deck(deck):
    """The example deck's text with its mesh path made absolute (relative to the deck's folder)
    and its solver section left out (each test writes its own)."""
    with open(deck) as f:
        text = f.read()
    folder = os.path.dirname(os.path.abspath(deck))
    text = text.replace("file: ", "file: " + folder + "/", 1)
    return "\n".join(line for line in text.splitlines() if not line.startswith("solver:"))


def write_deck(work, text):
    """TEXT written as WORK/deck.yaml; returns its path."""
    copy = os.path.join(work, "deck.yaml")
    with open(copy, "w") as f:
        f.write(text)
    return copy


def run_signorini(signorini, deck, out, n, mpirun, env, label, *extra):
    """`signorini run DECK -q -o OUT EXTRA...` on N ranks (one process when N is 1); exits with
    LABEL, the exit code and the output's tails when it fails. Returns (summary.json, stdout)."""
    cmd = [signorini, "run", deck, "-q", "-o", out] + list(extra)
    if n > 1:
        cmd = [mpirun, "-np", str(n)] + cmd
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit("%s: exit code %d\n%s\n%s" % (label, p.returncode, p.stdout[-3000:], p.stderr[-3000:]))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f), p.stdout


def launcher(**variables):
    """mpirun's path and the environment of the runs (root allowed, oversubscription allowed for
    more ranks than cores), with VARIABLES added; exits when mpirun is missing."""
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        sys.exit("mpirun not found (apt install openmpi-bin)")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", **variables)
    return mpirun, env


def read_vtu(path):
    """The Float64 arrays of a .vtu (raw appended data, UInt64 headers): {name: (components, values)}."""
    with open(path, "rb") as f:
        data = f.read()
    start = data.index(b'<AppendedData encoding="raw">')
    head, blob = data[:start].decode(), data[data.index(b"_", start) + 1:]
    out = {}
    for m in re.finditer(r'<DataArray type="Float64" Name="([^"]+)" NumberOfComponents="(\d+)"[^>]*offset="(\d+)"', head):
        name, comps, offset = m.group(1), int(m.group(2)), int(m.group(3))
        if name == "Points":
            continue
        size = struct.unpack_from("<Q", blob, offset)[0]
        out[name] = (comps, struct.unpack_from("<%dd" % (size // 8), blob, offset + 8))
    return out


def fields(folder, ranks):
    """The point and cell fields of the folder's last increment, from its .vtu or from the pieces
    its .pvtu joins (RANKS pieces), each point ordered by node_id and each cell by (body, cell_id), so that one
    rank's file and N ranks' pieces compare entry by entry."""
    joined = sorted(glob.glob(os.path.join(folder, "increment_*.pvtu")))
    if joined:
        with open(joined[-1]) as f:
            paths = [os.path.join(folder, p) for p in re.findall(r'<Piece Source="([^"]+)"', f.read())]
        assert len(paths) == ranks, "%s joins %d pieces, not %d" % (joined[-1], len(paths), ranks)
    else:
        paths = sorted(glob.glob(os.path.join(folder, "increment_*.vtu")))[-1:]
    points, cells = {}, {}
    names = None
    for path in paths:
        piece = read_vtu(path)
        names = names or sorted(piece)
        assert sorted(piece) == names, (path, sorted(piece), names)
        n_points, n_cells = len(piece["node_id"][1]), len(piece["cell_id"][1])
        for name, (comps, values) in piece.items():
            if len(values) == comps * n_points:
                for i, node in enumerate(piece["node_id"][1]):
                    points.setdefault(name, {})[node] = values[i * comps:(i + 1) * comps]
            else:
                assert len(values) == comps * n_cells, (path, name)
                for i, key in enumerate(zip(piece["body"][1], piece["cell_id"][1])):
                    assert key not in cells.get(name, {}), "cell %s is in two pieces" % (key,)
                    cells.setdefault(name, {})[key] = values[i * comps:(i + 1) * comps]
    out = {}
    for table in (points, cells):
        for name, by_key in table.items():
            out[name] = [v for key in sorted(by_key) for v in by_key[key]]
    return out


# Fields that measure the same quantity, by their names without a component suffix: a stress
# and a strain family; any other field is its own.
QUANTITY = {"stress": "stress", "von_mises": "stress", "back_stress": "stress", "contact_pressure": "stress",
            "strain": "strain", "plastic_strain": "strain", "equivalent_plastic_strain": "strain"}


def quantity_of(name):
    """The quantity a field measures: its tensor for a component ("plastic_strain" for
    "plastic_strain_yz"), and one family for the stresses and one for the strains (QUANTITY)."""
    tensor = re.sub(r"_[xyz]{1,2}$", "", name)
    return QUANTITY.get(tensor, tensor)


def agree(f1, f2, tolerance):
    """Asserts that two runs' fields (fields()) are the same fields and agree to TOLERANCE relative
    to the largest value of the quantity each measures (quantity_of); returns the largest such
    difference. A field that is zero up to round-off is so compared with its quantity, not with
    its own round-off: the shear plastic strain of a bar in tension (3e-18 against 8.5e-3), the
    contact pressure once Brinell's indenter has left (1e-92 against stresses of 490)."""
    assert sorted(f1) == sorted(f2), (sorted(f1), sorted(f2))
    largest = {}
    for name, values in f1.items():
        quantity = quantity_of(name)
        largest[quantity] = max(largest.get(quantity, 0.0), max((abs(v) for v in values if v == v), default=0.0))
    worst = 0.0

    def apart(a, b):
        """|a - b|; a value without value (NaN: the contact gap of a node with no master
        within reach) agrees with NaN only."""
        if a != a or b != b:
            return 0.0 if a != a and b != b else math.inf
        return abs(a - b)

    for name in f1:
        scale = max(largest[quantity_of(name)], 1e-300)
        err = max((apart(a, b) for a, b in zip(f1[name], f2[name])), default=0.0) / scale
        assert len(f1[name]) == len(f2[name]) and err <= tolerance, "field %s: %.2e apart" % (name, err)
        worst = max(worst, err)
    return worst
