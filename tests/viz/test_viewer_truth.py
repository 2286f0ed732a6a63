"""The 3-D view tells the truth: the spring is drawn between its two points as the body moves, a blow-up's tail
sets no arrow scale (the slides' Euler on the tennis racket once had ω drawn at 0.00174 m per rad/s: invisible),
and a still frames every arrow (the still of 00 once cut the push's arrow off at the top)."""
import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")
import rbcourse as rb  # noqa: E402
from rbcourse.rotation import project_so3  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.viz.viewer.draw import ARROW_CAP  # noqa: E402
from rbcourse.viz.viewer.parts import FOV  # noqa: E402
from rbcourse.examples import get_scene  # noqa: E402
from tests.viz.test_viewer import arrow_tips, clips, f32, objects, page_commands, rotate, traj_index  # noqa: E402


def test_the_spring_is_drawn_from_its_anchor_to_its_body_point_at_every_frame():
    ex = get_scene("box_on_spring")
    run = rb.simulate(ex.scene, ex.X0, 2.0, 2e-3, "rk4")
    d = viewer.draw_trajectory(run)
    cmds = page_commands(d.html())
    k = next(i for i, e in enumerate(ex.scene.effects) if isinstance(e, rb.Spring))
    spring = ex.scene.effects[k]
    path = f"/meshcat/springs/{k}"
    assert objects(cmds)[path + "/coil"]["object"]["type"] == "Line"
    c = clips(cmds)[path]
    times, anchor = c["position"]
    _, q = c["quaternion"]
    _, s = c["scale"]
    rows = traj_index(run, times, c["fps"])
    end = anchor + s[:, 1:2] * rotate(q, [0.0, 1.0, 0.0])                # the coil's far end: y = 1, stretched
    body_point = run.x[rows] + project_so3(run.R[rows]) @ spring.body_point
    np.testing.assert_allclose(anchor, np.broadcast_to(f32(spring.world_point), anchor.shape), atol=1e-6)
    np.testing.assert_allclose(end, body_point, atol=1e-5)
    assert np.ptp(s[:, 1]) > 0.05                                        # it stretches and shrinks with the motion
    assert any("spring" in words for _, words in d.legend)


def test_a_blow_up_sets_no_arrow_scale_and_its_tail_is_cut():
    ex = get_scene("tennis_racket")
    euler = rb.simulate(ex.scene, ex.X0, 20.0, 0.01, "euler", on_divergence="stop")
    assert euler.diverged
    d = viewer.draw_trajectory(euler)
    cmds = page_commands(d.html())
    _, tail, tip = arrow_tips(cmds, "/meshcat/arrows/omega_0")
    drawn = np.linalg.norm(tip - tail, axis=1)
    size = 2 * float(ex.scene.bodies[0].half_extents().max())
    arrow_length = 1.2 * size
    assert np.median(drawn) > 0.3 * arrow_length, "ω is drawn too small to see: the blow-up set its scale"
    assert drawn.max() <= ARROW_CAP * arrow_length * (1 + 1e-5)
    assert any(words.startswith("ω:") and "cut at" in words for _, words in d.legend)
    rk4 = viewer.draw_trajectory(rb.simulate(ex.scene, ex.X0, 5.0, 0.01, "rk4"))
    assert not any("cut at" in words for _, words in rk4.legend)          # a sane run: its largest sets the scale


def _view(cmds):
    """The camera's position relative to the point it looks at (world axes), and that point (the first frame)."""
    prop = next(c for c in cmds if c["type"] == "set_property" and c["path"] == "/Cameras/default/rotated/<object>"
                and c["property"] == "position")
    v = prop["value"]
    shift = next(c for c in cmds if c["type"] == "set_transform" and c["path"] == "/meshcat")["matrix"]
    return np.array([v[0], -v[2], v[1]]), -np.array(shift[12:15])


@pytest.mark.parametrize("follow", ["auto", None])
def test_a_still_frames_every_arrow(follow):
    body = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
    scene = rb.Scene(body, [rb.PointForce(body_point=(0.15, 0.1, 0.025), force=(0, 0, 10.0), frame="world")])
    X = rb.State.from_velocities(body, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=[0.3, 5.0, 0.2])
    cmds = page_commands(viewer.draw_state(scene, X, follow=follow).html())
    eye, target = _view(cmds)
    half = np.radians(FOV / 2)
    names = [c["path"] for c in cmds if c["type"] == "set_object" and c["path"].endswith("/head/mesh")]
    assert len(names) == 3                                               # ω, L and the push
    for name in names:
        arrow = name[: -len("/head/mesh")]
        group = next(c for c in cmds if c["type"] == "set_transform" and c["path"] == arrow)["matrix"]
        head = next(c for c in cmds if c["type"] == "set_transform" and c["path"] == arrow + "/head")["matrix"]
        M = np.array(group).reshape(4, 4).T
        tip = (M @ np.array([0.0, head[13] + objects(cmds)[name]["geometries"][0]["height"], 0.0, 1.0]))[:3]
        seen = tip - target - eye
        angle = np.arccos(seen @ -eye / np.linalg.norm(seen) / np.linalg.norm(eye))
        assert angle < 0.95 * half, f"{arrow}'s tip is at {np.degrees(angle):.1f}° from the view's axis (FOV/2 = {FOV / 2}°)"


def test_the_linked_views_plots_are_what_the_scene_conserves_and_stay_small():
    """draw_trajectory(traj, ghost=ref, plots=True): the heavy top's panels are its energy and L_z about the pivot
    (never |L|), ‖RᵀR − I‖ and the error against the reference; a curve of at most linked.POINTS points, each the
    largest of its stretch (a spike is not lost); an exact zero kept as 0; several runs, one curve each."""
    from rbcourse.viz.viewer import linked
    ex = get_scene("heavy_top")
    rk4 = rb.simulate(ex.scene, ex.X0, 1.0, ex.dt, "rk4")
    fine = rb.simulate(ex.scene, ex.X0, 1.0, ex.dt / 4, "rk4", record_every=4)
    euler = rb.simulate(ex.scene, ex.X0, 1.0, ex.dt, "euler", on_divergence="stop")
    d = viewer.draw_trajectory([rk4, euler], ghost=fine, ghost_label="rk4, dt/4", plots=True)
    keys = [p["key"] for p in d.plots["panels"]]
    assert keys == ["energy", "momentum", "orthogonality", "rotation"]
    assert "L_z about the pivot" in d.plots["panels"][1]["title"] and all("|L|" not in p["title"]
                                                                          for p in d.plots["panels"])
    assert [s["label"] for s in d.plots["series"]] == ["rk4", "euler"] and d.plots["series"][1]["end"] is not None
    for p in d.plots["panels"]:
        assert len(p["curves"]) == 2 and all(len(c["t"]) == len(c["v"]) <= linked.POINTS for c in p["curves"])
    energy = d.plots["panels"][0]["curves"][0]["v"]
    assert 0 < max(energy) < 1e-8                                        # rk4 keeps E to 1e-8 on the top
    assert linked.envelope(np.arange(1000.0), np.zeros(1000), points=10)[1].tolist() == [0.0] * 10   # exactly 0
    t, v = linked.envelope(np.arange(10_000.0), np.where(np.arange(10_000) == 4321, 1.0, 1e-9), points=100)
    assert len(t) == 100 and v.max() == 1.0                              # the spike survives the decimation
    side = viewer.draw_trajectory(rk4, ghost=euler, plots=True, ghost_is_reference=False)
    assert [p["key"] for p in side.plots["panels"]] == ["energy", "momentum", "orthogonality"]
    assert viewer.draw_trajectory(rk4).plots is None and "rbPlots" not in viewer.draw_trajectory(rk4).html()
    assert 'id="rb-plots"' in d.html() and len(d.html().encode()) < 300_000
