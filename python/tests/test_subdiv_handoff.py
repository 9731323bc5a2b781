"""`subdiv animate -o anim.usda` read back by Pixar's own USD library (PyPI ``usd-core``): the
stage opens, the mesh is Catmull-Clark with the cage's faces and tags, and the points at every
time code are the fitted cage of that frame (``subdiv animate -o DIR`` and ``subdiv deform
--frame N``), to the rounding of the 32-bit floats USD stores."""

from __future__ import annotations

import os

import numpy as np
import pytest

from conftest import ASSETS, run_cli

try:
    from pxr import Usd, UsdGeom
except ImportError:
    if os.environ.get("CI"):
        raise  # .ci/run installs usd-core: its absence there is an error
    pytest.skip("usd-core is not installed (pip install usd-core)", allow_module_level=True)

TUBE = ASSETS / "subdiv" / "tube-scene.json"
TUBE_OBJ = ASSETS / "subdiv" / "tube.obj"


def obj_vertices(text: str) -> np.ndarray:
    return np.array([[float(x) for x in line.split()[1:4]] for line in text.splitlines() if line.startswith("v ")])


def obj_faces(text: str) -> list[list[int]]:
    return [[int(v.split("/")[0]) - 1 for v in line.split()[1:]] for line in text.splitlines() if line.startswith("f ")]


def obj_creases(text: str) -> list[tuple[int, int, float]]:
    out = []
    for line in text.splitlines():
        words = line.split()
        if words[:2] == ["t", "crease"]:
            out.append((int(words[3]), int(words[4]), float(words[5])))
    return out


def f32_tolerance(points: np.ndarray) -> float:
    """Half an f32 ulp of the largest coordinate, with room for the decimal round trip."""
    return float(np.abs(points).max()) * 2.0**-23


@pytest.fixture(scope="module")
def handoff(tmp_path_factory):
    out = tmp_path_factory.mktemp("handoff")
    run_cli("subdiv", "animate", str(TUBE), "-o", str(out / "tube.usda"))
    run_cli("subdiv", "animate", str(TUBE), "-o", str(out / "frames"))
    return out


def test_the_stage_is_a_catmull_clark_mesh_with_the_cages_faces_and_creases(handoff):
    stage = Usd.Stage.Open(str(handoff / "tube.usda"))
    assert stage is not None
    mesh = UsdGeom.Mesh(stage.GetDefaultPrim())
    assert mesh, "the default prim is a Mesh"
    assert mesh.GetSubdivisionSchemeAttr().Get() == "catmullClark"
    assert mesh.GetInterpolateBoundaryAttr().Get() == "edgeAndCorner"
    text = TUBE_OBJ.read_text()
    faces = obj_faces(text)
    counts = list(mesh.GetFaceVertexCountsAttr().Get())
    indices = list(mesh.GetFaceVertexIndicesAttr().Get())
    assert counts == [len(f) for f in faces]
    assert indices == [v for f in faces for v in f]
    creases = obj_creases(text)
    assert creases, "the tube has a crease round its middle"
    assert list(mesh.GetCreaseLengthsAttr().Get()) == [2] * len(creases)
    assert list(mesh.GetCreaseIndicesAttr().Get()) == [v for a, b, _ in creases for v in (a, b)]
    assert np.allclose(list(mesh.GetCreaseSharpnessesAttr().Get()), [s for _, _, s in creases])
    ok, why = UsdGeom.Mesh.ValidateTopology(mesh.GetFaceVertexIndicesAttr().Get(),
                                            mesh.GetFaceVertexCountsAttr().Get(), len(obj_vertices(text)))
    assert ok, why
    assert UsdGeom.GetStageUpAxis(stage) == "Y"
    assert stage.GetTimeCodesPerSecond() == 24


def test_points_at_every_time_code_are_the_fitted_cage_of_that_frame(handoff, tmp_path):
    stage = Usd.Stage.Open(str(handoff / "tube.usda"))
    points = UsdGeom.Mesh(stage.GetDefaultPrim()).GetPointsAttr()
    codes = points.GetTimeSamples()
    frames = sorted((handoff / "frames").glob("frame-*.obj"))
    assert len(codes) == len(frames) == 97, (len(codes), len(frames))
    assert codes == list(range(97)), "frame k at time code k (24 fps, 4 s)"
    rest = obj_vertices(TUBE_OBJ.read_text())
    diagonal = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    worst = 0.0
    for code, frame in zip(codes, frames):
        want = obj_vertices(frame.read_text())
        got = np.array(points.Get(code), dtype=np.float64)
        error = np.abs(got - want).max()
        assert error <= f32_tolerance(want), f"time code {code}: {error}"
        worst = max(worst, error / diagonal)
    print(f"USD points against the fitted cages: {worst:.3g} of the diagonal (f32 rounding)")
    # The frames are animate's own; `subdiv deform --frame N` gives the same cage.
    for n in (0, 30, 72):
        out = tmp_path / f"frame{n}.obj"
        run_cli("subdiv", "deform", str(TUBE), "--frame", str(n), "-o", str(out))
        assert out.read_text() == frames[n].read_text(), f"frame {n}"
    # Frames move: a control frame differs.
    assert np.abs(np.array(points.Get(30)) - np.array(points.Get(0))).max() > 0.1 * diagonal


def test_python_writes_what_the_command_line_writes(handoff, tmp_path):
    import splineskin

    rig = splineskin.SubdivRig.from_scene(TUBE)
    times, cages = rig.animation()
    assert times.shape == (97,) and cages.shape == (97, rig.n_vertices, 3)
    assert times[-1] == 4.0
    frames = sorted((handoff / "frames").glob("frame-*.obj"))
    assert np.abs(cages[30] - obj_vertices(frames[30].read_text())).max() <= 1e-12
    rig.write_animation(tmp_path / "tube.usda")
    assert (tmp_path / "tube.usda").read_text() == (handoff / "tube.usda").read_text()
    rig.write_animation(tmp_path / "tube.glb", level=2)
    run_cli("subdiv", "animate", str(TUBE), "-o", str(tmp_path / "cli.glb"), "--level", "2")
    assert (tmp_path / "tube.glb").read_bytes() == (tmp_path / "cli.glb").read_bytes()
    with pytest.raises(ValueError, match="expected a name ending in .usda"):
        rig.write_animation(tmp_path / "tube.fbx")
    assert not (tmp_path / "tube.fbx").exists()
