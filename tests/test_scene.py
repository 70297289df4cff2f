"""Scene validation: unknown keys, wrong types and out-of-range values name the key."""
import numpy as np
import pytest

from fsi.setup.build import build
from fsi.scene import SCHEMA, SceneError, bundled_scenes, load_scene, parse_scene


def test_bundled_scenes_load_and_thesis_static_is_table_4_1():
    assert {"thesis-static", "thesis-ramp", "diaphragm-static",
            "diaphragm-fill"} <= set(bundled_scenes())
    assert load_scene("diaphragm-static")["structure"]["model"] == "auto"
    s = load_scene("thesis-static")
    assert s["membrane"] == dict(grid_size=26, thickness=0.001778, density=1070.0,
                                 youngs_modulus=8.6e6, poisson_ratio=0.5, shape="hemisphere",
                                 support="clamped", wrinkling="none",
                                 grading_band=[0.0, 1.0], grading_density=1.0)
    assert s["structure"]["model"] == "thesis"
    assert s["tank"]["radius"] == 0.20955
    assert s["liquid"]["body_acceleration"] == [0.0, 0.0, -9.81]
    assert s["constraints"]["error_limit"] == 1.0
    assert s["constraints"]["bend_limit_iterations"] == 10
    assert len(s["sweep"]["fills"]) == 11
    r = load_scene("thesis-ramp")["thesis"]
    assert (r["dt"], r["end_time"], r["height_start"], r["height_end"]) == (1e-4, 5.0, -1.05, 1.05)


@pytest.mark.parametrize("text,key,allowed", [
    ("[membrane]\nthickness = -0.001", "membrane.thickness", "> 0 m"),
    ("[membrane]\ngrid_size = 25", "membrane.grid_size", "even integer >= 4"),
    ("[membrane]\ngrid_size = 2", "membrane.grid_size", "even integer >= 4"),
    ("[membrane]\ngrid_size = 26.0", "membrane.grid_size", "expected int"),
    ("[sweep]\nfills = [0.2, 1.5]", "sweep.fills", "[0, 1]"),
    ("[sweep]\nfills = [-0.1]", "sweep.fills", "[0, 1]"),
    ("[constraints]\nerror_limit = 0", "constraints.error_limit", "0 < value < 100"),
    ("[liquid]\nbody_acceleration = [0, -9.81]", "liquid.body_acceleration", "three"),
    ("[thesis]\ndamping = 'heavy'", "thesis.damping", "courant-drag"),
    ("[scene]\nprocedure = 'dance'", "scene.procedure", "volume-sweep"),
    ("[membrane]\nthicknes = 0.001", "membrane.thicknes", "allowed in [membrane]"),
    ("[membrne]\nthickness = 0.001", "membrne", "allowed"),
    ("[constraints]\nself_collision = 1", "constraints.self_collision", "expected bool"),
    ("[port]\nramp_time = 0.0", "port.ramp_time", "> 0 s"),
    ("[coupling]\nacceleration = 'newton'", "coupling.acceleration", "'iqn-ils'"),
    ("[coupling]\non_max_iterations = 'ignore'", "coupling.on_max_iterations", "'accept'"),
    # the answers a stalled window no bundled scene takes are retired with their keys
    # (docs/notes/minimisation-statics.md, 'What the coupling still needs')
    ("[coupling]\non_max_iterations = 'newton'", "coupling.on_max_iterations", "'split'"),
    ("[coupling]\nnewton_iterations = 10", "coupling.newton_iterations",
     "allowed in [coupling]"),
    ("[coupling]\nmixing = 0.0", "coupling.mixing", "0 < value <= 1"),
    ("[scene]\nprocedure = 'coupled-fill'\n[coupling]\non_max_iterations = 'accept-best'\n"
     "stall_iterations = 30", "coupling.stall_iterations", "allowed: 0"),
    ("[scene]\nprocedure = 'coupled-fill'\n[coupling]\non_max_iterations = 'split'\n"
     "stall_reduction = 1.0", "coupling.stall_reduction", "0 < value < 1"),
    ("[scene]\nprocedure = 'coupled-fill'\n[coupling]\non_max_iterations = 'accept'\n"
     "split_unconverged = 'window'", "coupling.split_unconverged", "allowed: 'parts'"),
    ("[dynamics]\nstart_fill = 1.0", "dynamics.start_fill", "0 < value < 1"),
    ("[fluid]\ncells = 4", "fluid.cells", "8..128"),
    ("[fluid]\nlevel_plane = 'cells'", "fluid.level_plane", "'faces'"),
    ("[scene]\nprocedure = 'coupled-fill'\n[structure]\nmodel = 'shell'", "structure.model",
     "'xpbd'"),
    ("[scene]\nprocedure = 'coupled-fill'\n[dynamics]\nwindow = 1e-7\nend_time = 1.0",
     "dynamics.window", "1e6"),
])
def test_bad_scene_raises_naming_key_and_range(text, key, allowed):
    with pytest.raises(SceneError) as err:
        parse_scene(text)
    assert key in str(err.value) and allowed in str(err.value)


def test_a_plane_of_faces_at_the_level_is_refused_under_a_membrane():
    """fluid.level_plane moves the grid under a free surface only: a coupled fill (the liquid
    under the membrane) refuses it before running, naming the key."""
    from fsi.setup.build import build

    scene = parse_scene("[scene]\nprocedure = 'coupled-fill'\n[fluid]\nlevel_plane = 'faces'\n")
    with pytest.raises(SceneError, match=r"fluid\.level_plane.*allowed: 'anywhere'"):
        build(scene)


def test_unresolved_port_raises_before_running():
    from fsi.setup.build import build

    scene = parse_scene("[scene]\nprocedure = 'coupled-fill'\n[port]\nradius = 0.02\n"
                        "[fluid]\ncells = 16")
    with pytest.raises(SceneError, match=r"port\.radius.*1\.5 cells.*fluid\.cells = 16"):
        build(scene)
    scene = parse_scene("[scene]\nprocedure = 'coupled-fill'\n[port]\nlength = 0.05\n")
    with pytest.raises(SceneError, match=r"port\.length.*2\.0 cells"):
        build(scene)


def test_time_step_breaking_courant_limit_raises_before_running():
    scene = parse_scene("[scene]\nprocedure = 'thesis-ramp'\n[thesis]\ndt = 0.01")
    with pytest.raises(SceneError, match=r"thesis\.dt.*Courant.*allowed 0 < dt <"):
        build(scene)
    build(parse_scene("[scene]\nprocedure = 'thesis-ramp'\n[membrane]\ngrid_size = 6"))


def test_every_schema_default_passes_its_own_check():
    for section, keys in SCHEMA.items():
        for name, key in keys.items():
            if key.default is not None:
                assert key.check(key.default), f"{section}.{name}"


def test_missing_scene_file_raises(tmp_path):
    with pytest.raises(SceneError, match="not found"):
        load_scene(str(tmp_path / "nope.toml"))


def test_structure_model_key():
    scene = parse_scene("[structure]\nmodel = 'xpbd'\n[membrane]\ngrid_size = 6")
    assert build(scene).structure_model == "xpbd"
    with pytest.raises(SceneError, match="structure.model.*thesis-ramp"):
        parse_scene("[scene]\nprocedure = 'thesis-ramp'\n[structure]\nmodel = 'shell'")
    with pytest.raises(SceneError, match="structure.model"):
        parse_scene("[structure]\nmodel = 'ansys'")
    assert build(parse_scene("[scene]\nprocedure = 'thesis-ramp'\n[membrane]\ngrid_size = 6")
                 ).structure_model == "thesis"


def test_membrane_shape_key_builds_the_disc_where_the_procedure_runs_it():
    """``membrane.shape = "disc"``: a flat sheet across the equator (every node at z = 0, the
    rim on r = R) in the coupled fill and the diaphragm's slosh; refused by name in a
    procedure that runs the hemisphere only (from a file or from ``with_keys``) and by a
    slosh surface without a membrane."""
    setup = build(load_scene("diaphragm-fill").with_keys({"membrane": {"shape": "disc"}}))
    x, r = setup.model.node_rest_position, setup.model.radius
    assert np.abs(x[:, 2]).max() == 0.0
    assert np.hypot(x[:, 0], x[:, 1]).max() == pytest.approx(r, rel=1e-12)
    hemisphere = build(load_scene("diaphragm-fill")).model.node_rest_position
    np.testing.assert_allclose(np.linalg.norm(hemisphere, axis=1), r, rtol=1e-9)
    assert hemisphere[:, 2].min() < -0.9 * r  # the default: against the lower wall
    with pytest.raises(SceneError, match="membrane.shape.*volume-sweep.*'hemisphere' only"):
        parse_scene("[membrane]\nshape = 'disc'")
    with pytest.raises(SceneError, match="membrane.shape.*thesis-ramp procedure"):
        load_scene("thesis-ramp").with_keys({"membrane": {"shape": "disc"}})
    with pytest.raises(SceneError, match="membrane.shape.*'limp' has no membrane"):
        build(load_scene("slosh-half").with_keys({"membrane": {"shape": "disc"}}))
    disc = build(load_scene("slosh-diaphragm").with_keys({"membrane": {"shape": "disc"}}))
    assert np.abs(disc.model.node_rest_position[:, 2]).max() == 0.0
    with pytest.raises(SceneError, match="membrane.shape"):
        parse_scene("[membrane]\nshape = 'cone'")


def test_grading_keys_move_the_rings_into_their_band_and_are_refused_out_of_range():
    """``membrane.grading_band`` and ``grading_density``: the scene's sheet is the graded
    grid (:class:`structure.grid.Grading`), the default is App. C's bit for bit, and a band
    or density out of range is refused naming the key and its range."""
    from structure.grid import Grading, hemisphere_grid

    scene = load_scene("diaphragm-static")
    n, r = scene["membrane"]["grid_size"], scene["tank"]["radius"]
    assert np.array_equal(build(scene).model.node_rest_position, hemisphere_grid(n, r))
    graded = build(scene.with_keys({"membrane": {"grading_band": [0.6, 0.9],
                                                 "grading_density": 2.5}}))
    np.testing.assert_array_equal(graded.model.node_rest_position,
                                  hemisphere_grid(n, r, Grading((0.6, 0.9), 2.5)))
    with pytest.raises(SceneError, match=r"membrane\.grading_band.*0 <= start < stop <= 1"):
        parse_scene("[membrane]\ngrading_band = [0.9, 0.6]")
    with pytest.raises(SceneError, match=r"membrane\.grading_density.*>= 1"):
        parse_scene("[membrane]\ngrading_density = 0.5")
    # the volume sweep's XPBD full inversion cannot take a first step on the band's cells at
    # N = 50 whatever its dt: the refusal names the grading too
    with pytest.raises(SceneError, match=r"relaxation\.dt.*membrane\.grading_density \(now 3"):
        build(scene.with_keys({"membrane": {"grid_size": 50, "grading_band": [0.15, 0.4],
                                            "grading_density": 3.0}}))


@pytest.mark.parametrize("name", ["thesis-fill", "thesis-drain"])
def test_thesis_fill_and_drain_span_tank_fraction_0_1_to_0_9(name):
    """The thesis's fill and drain (docs/notes/slow-fills.md): end_time takes the port's flow
    from tank fraction 0.1 to 0.9 or back."""
    setup = build(load_scene(name))
    dyn = setup.scene["dynamics"]
    tank = 4.0 / 3.0 * 3.141592653589793 * setup.model.radius**3
    flow, ramp = setup.scene["port"]["flow"], setup.scene["port"]["ramp_time"]
    end_fill = dyn["start_fill"] + flow * (dyn["end_time"] - ramp / 2) / tank
    assert end_fill == pytest.approx(0.9 if flow > 0 else 0.1, abs=1e-6)


SPLIT_UNCONVERGED_BY_SCENE = {"valve-fill": "parts", "valve-drain": "window"}
"""What each valve scene keeps of a split whose smallest parts stall (docs/notes/split-windows.md,
'A split that does not converge')."""


@pytest.mark.parametrize("name, start, end", [("valve-fill", 0.1, 0.9),
                                               ("valve-drain", 0.9, 0.1)])
def test_valve_fill_and_drain_span_0_1_to_0_9_with_mixing_in_their_coupling(name, start, end):
    """The valve fill and drain (docs/notes/valve-fill.md, 'With mixing'): they start at one
    end of 0.1..0.9, their windows end at or past the other, within one window, their coupling
    carries mixing, their pressure is fitted from each window's starting cells
    (docs/notes/pressure-cells.md), the liquid gets each window's mean velocity
    (docs/notes/valve-drain.md, 'The velocity the liquid sees'), and a stalled window is split
    three times at most, a try stopped after 30 iterations without halving its best residual
    (docs/notes/split-windows.md)."""
    from fsi.procedures.coupled import coupling_settings

    setup = build(load_scene(name))
    dyn, port = setup.scene["dynamics"], setup.scene["port"]
    tank = 4.0 / 3.0 * 3.141592653589793 * setup.model.radius**3
    end_fill = dyn["start_fill"] + port["flow"] * (dyn["end_time"] - port["ramp_time"] / 2) / tank
    assert dyn["start_fill"] == start
    beyond = abs(port["flow"]) * dyn["window"] / tank
    assert 0.0 <= (end_fill - end) * np.sign(port["flow"]) < beyond
    settings = coupling_settings(setup.scene["coupling"])
    assert settings.acceleration == "iqn-ils"
    assert settings.acceleration_settings.mixing == 0.1
    assert settings.acceleration_settings.reuse == 0
    assert setup.scene["fluid"]["pressure_cells"] == "window"
    assert setup.scene["coupling"]["interface_velocity"] == "window-mean"
    assert (settings.on_max_iterations, settings.split_depth, settings.stall_iterations) == \
        ("split", 3, 30)
    assert settings.split_unconverged == SPLIT_UNCONVERGED_BY_SCENE[name]


def test_accept_residual_reaches_the_coupling_and_is_checked():
    from fsi.procedures.coupled import coupling_settings

    scene = load_scene("valve-drain")
    assert coupling_settings(scene.with_keys({"coupling": {"accept_residual": 0.1}})["coupling"]
                             ).accept_residual == 0.1
    assert coupling_settings(load_scene("valve-open")["coupling"]).accept_residual == np.inf
    with pytest.raises(SceneError, match="coupling.accept_residual"):
        scene.with_keys({"coupling": {"accept_residual": 0.0}})


def test_pressure_fit_and_centre_cells_reach_the_liquid_and_are_checked():
    """``fluid.pressure_fit`` reaches the liquid's model, ``fluid.centre_cells`` its
    participant (docs/notes/stalled-windows.md); both default to the liquid's map as it
    was."""
    from types import SimpleNamespace

    from fsi.procedures.coupled_fill import assemble, membrane_settings
    from structure.model import MembraneState
    from structure.xpbd import XpbdModel

    scene = load_scene("diaphragm-fill").with_keys({"membrane": {"grid_size": 6},
                                                    "fluid": {"cells": 12},
                                                    "port": {"radius": 0.07, "length": 0.1}})
    for fit, centres in ((None, None), ("tapered", "window")):
        keys = {} if fit is None else {"fluid": {"pressure_fit": fit, "centre_cells": centres}}
        setup = build(scene.with_keys(keys))
        model = XpbdModel.from_membrane(setup.model)
        parts = assemble(setup, model, membrane_settings(setup),
                         MembraneState(setup.model.node_rest_position),
                         SimpleNamespace(pressure_level=0.0))
        assert parts.fluid.model.pressure_fit == (fit or "block")
        assert parts.fluid_side.centre_cells == (centres or "iteration")
    for key in ("pressure_fit", "centre_cells"):
        with pytest.raises(SceneError, match=f"fluid.{key}"):
            scene.with_keys({"fluid": {key: "smooth"}})


def test_interface_velocity_reaches_the_membrane_and_is_checked():
    """``coupling.interface_velocity`` picks what the membrane sends the liquid
    (docs/notes/valve-drain.md, 'The velocity the liquid sees'); the default is the
    membrane's own end velocity."""
    from types import SimpleNamespace

    from fsi.coupled.adapters import INTERFACE_VELOCITIES
    from fsi.procedures.coupled_fill import assemble, membrane_settings
    from structure.model import MembraneState
    from structure.xpbd import XpbdModel

    scene = load_scene("diaphragm-fill").with_keys({"membrane": {"grid_size": 6},
                                                    "fluid": {"cells": 12},
                                                    "port": {"radius": 0.07, "length": 0.1}})
    for name in (None, "window-mean"):
        keys = {} if name is None else {"coupling": {"interface_velocity": name}}
        setup = build(scene.with_keys(keys))
        model = XpbdModel.from_membrane(setup.model)
        rest = MembraneState(setup.model.node_rest_position)
        parts = assemble(setup, model, membrane_settings(setup), rest,
                         SimpleNamespace(pressure_level=0.0))
        assert parts.membrane.velocity is INTERFACE_VELOCITIES[name or "membrane"]
    with pytest.raises(SceneError, match="coupling.interface_velocity"):
        scene.with_keys({"coupling": {"interface_velocity": "end"}})
    # the window's mean is backward Euler's velocity: refused with BDF2 windows, by name
    for name in ("diaphragm-fill", "slosh-diaphragm"):
        bdf2 = load_scene(name).with_keys({"coupling": {"interface_velocity": "window-mean",
                                                        "time_scheme": "bdf2"}})
        with pytest.raises(SceneError, match="coupling.interface_velocity.*'membrane'"):
            build(bdf2)


def test_with_keys_changes_a_copy_and_checks_each_value():
    scene = load_scene("diaphragm-fill")
    changed = scene.with_keys({"dynamics": {"window": 0.004, "end_time": 1}})
    assert changed["dynamics"]["window"] == 0.004 and changed["dynamics"]["end_time"] == 1.0
    assert isinstance(changed["dynamics"]["end_time"], float)  # coerced as a file's is
    assert scene["dynamics"]["window"] == 0.002 and changed["port"] == scene["port"]
    with pytest.raises(SceneError, match="dynamics.window"):
        scene.with_keys({"dynamics": {"window": -1.0}})
    with pytest.raises(SceneError, match="membrane.colour"):
        scene.with_keys({"membrane": {"colour": "red"}})
