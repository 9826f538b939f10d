"""The Foxglove JSON Schemas homesim writes into its MCAP exports are Foxglove's own, unmodified.

Each vendored file's git blob id must be the one of the same file in the
foxglove-sdk repository at tag ``typescript/schemas/v2.1.0`` (the published
``@foxglove/schemas`` 2.1.0), so an edit to a schema, or a file from another
release, fails here; updating means copying the new release verbatim and
changing these ids and ``FOXGLOVE_SCHEMAS_VERSION``.
"""

from __future__ import annotations

import hashlib
import json
from importlib import resources

import pytest

from homesim.export import foxglove as fg

#: ``git ls-tree typescript/schemas/v2.1.0 schemas/jsonschema/`` in foxglove-sdk.
UPSTREAM_BLOBS = {
    "FrameTransforms.json": "260a1920e3e85d343cbccdd5bf8501810c4be9f9",
    "LaserScan.json": "317521f469d1cca57867d64b654262a01f86f9b8",
    "Log.json": "48fb50a53c1334e582f812e884dd9004b2b871c4",
    "PoseInFrame.json": "ffae7f962e90275b2ed4a8d0ee3cfbb576f41364",
    "SceneUpdate.json": "9a1e0c6aa793a199dcd30fbd0ce9a6581ac13d29",
}
#: The MIT licence of the same tag.
LICENCE_BLOB = "0aa593ea8c2888c2015f0aec7e6d6a1c42cfeba1"


def _blob(data: bytes) -> str:
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def _vendored(name: str) -> bytes:
    return resources.files("homesim.export").joinpath("foxglove_schemas", name).read_bytes()


@pytest.mark.parametrize("name", sorted(UPSTREAM_BLOBS))
def test_vendored_schema_is_foxgloves_file_byte_for_byte(name):
    assert _blob(_vendored(name)) == UPSTREAM_BLOBS[name]


def test_the_licence_and_version_come_with_them():
    assert _blob(_vendored("LICENSE")) == LICENCE_BLOB
    assert fg.FOXGLOVE_SCHEMAS_VERSION in _vendored("README.md").decode("utf-8")
    assert {f"{n}.json" for n in fg.FOXGLOVE_SCHEMAS} == set(UPSTREAM_BLOBS)


@pytest.mark.parametrize("name", [f"foxglove.{n}" for n in fg.FOXGLOVE_SCHEMAS])
def test_the_exporter_writes_the_vendored_bytes(name):
    data = fg.schema_bytes(name)
    assert data == _vendored(name[9:] + ".json") and json.loads(data)["title"] == name


def test_builders_fill_every_field_foxglove_requires():
    import jsonschema

    ent = fg.entity(5, "map", "e", metadata={"k": "v"}, lines=[fg.line([fg.vec(0, 0), fg.vec(1, 0)], fg.color(1, 0, 0))],
                    texts=[fg.text(0, 0, 0, "t")])
    jsonschema.validate(fg.scene_update([ent], [fg.deletion(5), fg.deletion(5, "old")]), fg.schema("foxglove.SceneUpdate"))
    jsonschema.validate(fg.pose_in_frame(1_500_000_000, "map", 1.0, 2.0, 0.5), fg.schema("foxglove.PoseInFrame"))
    jsonschema.validate(fg.log(7, "robot", "Hello"), fg.schema("foxglove.Log"))
    with pytest.raises(TypeError):
        fg.entity(0, "map", "e", boxes=[])
    with pytest.raises(KeyError):
        fg.schema_bytes("foxglove.NotASchema")
