"""The MCAP's `/grasp/scene` topic: foxglove.SceneUpdate messages that Foxglove's own message
types (the foxglove-sdk package, an independent definition) accept field for field and encode,
with the object drawn as its shape and one normal and one friction arrow per loaded finger."""

import json

import pytest

import grasp
from conftest import EXAMPLES, checker

messages = checker("foxglove.messages", reason="foxglove-sdk is installed by scripts/install-checkers.sh")
mcap_reader = checker("mcap.reader", reason="mcap is installed by scripts/install-checkers.sh")

# The Foxglove type of each JSON field that holds a message (or a list of them).
TYPES = {
    "entities": messages.SceneEntity, "deletions": messages.SceneEntityDeletion,
    "arrows": messages.ArrowPrimitive, "cubes": messages.CubePrimitive,
    "spheres": messages.SpherePrimitive, "triangles": messages.TriangleListPrimitive,
    "cylinders": messages.CylinderPrimitive, "lines": messages.LinePrimitive,
    "texts": messages.TextPrimitive, "models": messages.ModelPrimitive,
    "metadata": messages.KeyValuePair, "pose": messages.Pose, "position": messages.Vector3,
    "orientation": messages.Quaternion, "size": messages.Vector3, "points": messages.Point3,
    "color": messages.Color, "colors": messages.Color, "timestamp": messages.Timestamp,
    "lifetime": messages.Duration,
}


def build(cls, fields):
    """`cls(**fields)` with nested messages built the same way: an unknown field or a value of
    the wrong type raises."""
    kwargs = {}
    for key, value in fields.items():
        inner = TYPES.get(key)
        if inner is None:
            kwargs[key] = value
        elif isinstance(value, list):
            kwargs[key] = [build(inner, v) for v in value]
        else:
            kwargs[key] = build(inner, value)
    return cls(**kwargs)


def scene_messages(path):
    with open(path, "rb") as f:
        reader = mcap_reader.make_reader(f)
        return [(schema.name, schema.encoding, channel.message_encoding, json.loads(msg.data))
                for schema, channel, msg in reader.iter_messages(topics=["/grasp/scene"])]


def test_scene_updates_are_foxglove_messages(tmp_path):
    schedule = {"time": {"start": 0, "end": 1, "step": 0.25},
                "fingers": {"right": [{"ramp": {"keyframes": [[0, 10], [1, 20]]}}]}}
    path = tmp_path / "pinch.mcap"
    run = grasp.transfer(grasp.Scene(EXAMPLES / "box_pinch.json"), schedule, mcap=path)
    found = scene_messages(path)
    assert len(found) == len(run) + 1  # the object once, then the forces of every step
    for name, schema_encoding, encoding, data in found:
        assert (name, schema_encoding, encoding) == ("foxglove.SceneUpdate", "jsonschema", "json")
        update = build(messages.SceneUpdate, data)
        assert len(update.encode()) > 0
    obj = found[0][3]["entities"][0]
    assert obj["id"] == "object" and len(obj["triangles"][0]["indices"]) == 36  # a box: 12 triangles
    tips = found[0][3]["entities"][2]
    assert tips["id"] == "fingertips" and len(tips["cubes"]) == 2  # the jaws' flat pads
    forces = [e for _, _, _, d in found[1:] for e in d["entities"]]
    assert all(len(e["arrows"]) == 4 for e in forces)  # normal and friction, two fingers


def test_a_scene_without_a_shape_draws_the_box_around_its_contacts(tmp_path):
    path = tmp_path / "plate.mcap"
    grasp.transfer(grasp.Scene(EXAMPLES / "plate_transfer.json"), EXAMPLES / "plate_transfer.schedule.json", mcap=path)
    found = scene_messages(path)
    assert found[0][3]["entities"][0]["cubes"] and not found[0][3]["entities"][0]["triangles"]
    for _, _, _, data in found[:3]:
        build(messages.SceneUpdate, data).encode()


@pytest.mark.parametrize("tip,kind", [({"cylinder": {"radius": 0.01, "axis": [0, 1, 0]}}, "cylinders"),
                                      ({"sphere": {"radius": 0.01}}, "spheres")])
def test_curved_fingertips_are_foxglove_primitives_touching_the_contact(tmp_path, tip, kind):
    with open(EXAMPLES / "hertz_sphere_on_flat.json") as f:
        scene = json.load(f)
    finger = scene["fingers"][0]
    del finger["tip_radius"]
    finger["tip"] = tip
    path = tmp_path / "tip.mcap"
    grasp.transfer(grasp.Scene(scene), {"time": {"start": 0, "end": 1, "step": 0.5}, "fingers": {}}, mcap=path)
    first = scene_messages(path)[0][3]
    build(messages.SceneUpdate, first)
    (tips,) = [e for e in first["entities"] if e["id"] == "fingertips"]
    (shape,) = tips[kind]
    # Diameter 20 mm; the centre 10 mm below the contact (normal +z, the finger below).
    assert shape["size"]["x"] == pytest.approx(0.02, abs=1e-15)
    centre = shape["pose"]["position"]
    assert (centre["x"], centre["y"], centre["z"]) == pytest.approx((0.0, 0.0, -0.01), abs=1e-15)
    if kind == "cylinders":
        # The pose turns the cylinder's z axis onto the tip's axis (y): q = rotation about x.
        q = shape["pose"]["orientation"]
        assert abs(q["x"]) == pytest.approx(2 ** -0.5, abs=1e-12) and q["y"] == pytest.approx(0, abs=1e-12)
