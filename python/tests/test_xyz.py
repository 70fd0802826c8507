"""Extended XYZ from Python through the library's reader and writer: a trajectory the CLI
wrote (`spheresweep run`) read into arrays that match the same run done from Python, and
frames a simulation writes read back bit for bit (by the Rust reader, and as plain text)."""

import pathlib
import subprocess

import numpy as np
import pytest

import spheresweep as ss

from test_core import rust_cli

ROOT = pathlib.Path(__file__).resolve().parents[2]

SCENE = """
[run]
t_end = 2.0
snapshot_every = 1.0

[boundary]
kind = "periodic"

[[generate]]
kind = "periodic_gas"
n = 300
phi = 0.2
radius = 0.5
temperature = 1.0
"""


def test_a_trajectory_the_cli_wrote_reads_as_the_python_run(tmp_path):
    scene = tmp_path / "gas.toml"
    scene.write_text(SCENE)
    subprocess.run([rust_cli(), "run", str(scene), "--out", str(tmp_path / "out"), "--quiet"],
                   check=True, capture_output=True)
    frames = ss.read_xyz(tmp_path / "out" / "trajectory.xyz")
    assert [f["time"] for f in frames] == [0.0, 1.0, 2.0]
    sim = ss.Simulation.from_scene_file(str(scene))
    for frame in frames:
        sim.advance_to(frame["time"])
        assert frame["box"] == sim.box
        assert np.array_equal(frame["positions"], sim.positions)  # bit for bit
        assert np.array_equal(frame["velocities"], sim.velocities)
        assert np.array_equal(frame["radii"], sim.radii)
        assert frame["materials"].dtype == np.uint16 and (frame["materials"] == 0).all()


def test_frames_written_from_python_read_back_bit_for_bit(tmp_path):
    path = tmp_path / "frames.xyz"
    sim = ss.Simulation.from_spheres([[0.1, 0.2, 0.3], [5, 5, 5]], [[1e-300, -2, 1 / 3], [0, 0, 0]],
                                     [0.5, 0.25], materials=[2, 0])
    sim.write_xyz(path)
    sim.advance_to(0.7)
    sim.write_xyz(path)
    frames = ss.read_xyz(path)
    assert [f["time"] for f in frames] == [0.0, 0.7] and frames[0]["box"] is None
    assert np.array_equal(frames[1]["positions"], sim.positions)
    assert np.array_equal(frames[0]["velocities"][0], [1e-300, -2, 1 / 3])
    assert frames[0]["materials"].tolist() == [2, 0]
    # The text is the format OVITO and ASE read: a count, the comment line, a line a sphere.
    lines = path.read_text().splitlines()
    assert lines[0] == "2" and 'pbc="F F F"' in lines[1] and "Properties=species:S:1:pos:R:3" in lines[1]
    assert lines[2].split()[0] == "X" and len(lines[2].split()) == 9


def test_a_malformed_file_names_the_line(tmp_path):
    path = tmp_path / "bad.xyz"
    path.write_text("2\nProperties=species:S:1:pos:R:3:radius:R:1\nX 1 2 3 0.5\n")
    with pytest.raises(ValueError, match=r"bad.xyz: line 4: the frame ends after 1 of its 2"):
        ss.read_xyz(path)
    with pytest.raises(OSError, match="no-such.xyz"):
        ss.read_xyz(tmp_path / "no-such.xyz")
