"""The HTTP API's schema keeps its promises: every path, parameter, form field and answer field of the released schema
(``tests/data/openapi-0.1.0.json``, the schema ``exprclone serve`` 0.1.0 served) answers as it did; and the options'
answer (``GET /api/options``) says of each option what the schema says of its form field."""

import copy
import json
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from exprclone.options import VALUES, key, names, offered, spec
from exprclone.server.app import create_app

RELEASED = Path(__file__).resolve().parents[1] / "data" / "openapi-0.1.0.json"
#: what the released schema said and the server never did (no client of it met it), each with what the server does: the
#: schema's correction is no change to a client.
CORRECTED = {
    "GET /api/samples/{name} 200 application/json: gone": "a sample was always answered as its file: a JPEG photo or an MP4 video",
}


def resolve(schema: dict, node: dict) -> dict:
    """``node`` with its ``$ref`` followed into ``schema``'s components."""
    while "$ref" in node:
        node = schema["components"]["schemas"][node["$ref"].rsplit("/", 1)[1]]
    return node


def types(node: dict) -> set[str]:
    """The JSON types a schema node allows (``anyOf`` included)."""
    found = {node["type"]} if "type" in node else set()
    for part in node.get("anyOf", []):
        found |= types(part)
    return found


def changes(before: dict, after: dict, old: dict, new: dict, where: str, asked: bool) -> list[str]:
    """What a client of ``old`` (a node of the schema ``before``) would find changed in ``new`` (of ``after``): a type
    gone, a field gone, a value no longer taken; for a request (``asked``) also a field newly required, and for an answer
    a field no longer promised."""
    old, new = resolve(before, old), resolve(after, new)
    found = [f"{where}: type {sorted(types(old))} became {sorted(types(new))}"] if not types(old) <= types(new) and types(new) else []
    if asked and not set(old.get("enum", new.get("enum", []))) <= set(new.get("enum", old.get("enum", []))):
        found.append(f"{where}: no longer takes {sorted(set(old['enum']) - set(new['enum']))}")
    if asked and old.get("pattern") != new.get("pattern"):
        found.append(f"{where}: pattern {old.get('pattern')} became {new.get('pattern')}")
    for name, field in old.get("properties", {}).items():
        if name not in new.get("properties", {}):
            found.append(f"{where}.{name}: gone")
        else:
            found += changes(before, after, field, new["properties"][name], f"{where}.{name}", asked)
    values = old.get("additionalProperties")
    if isinstance(values, dict):  # a dict's values: each field of the model that replaced it is one
        for name, field in new.get("properties", {}).items():
            found += changes(before, after, values, field, f"{where}.{name}", asked)
    if "items" in old and "items" in new:
        found += changes(before, after, old["items"], new["items"], f"{where}[]", asked)
    required_old, required_new = set(old.get("required", [])), set(new.get("required", []))
    if asked and required_new - required_old:
        found.append(f"{where}: newly required {sorted(required_new - required_old)}")
    if not asked and required_old - required_new:
        found.append(f"{where}: no longer promises {sorted(required_old - required_new)}")
    return found


def differences(before: dict, after: dict) -> list[str]:
    """Everything a client of ``before`` would find changed in ``after`` (additions are no change)."""
    found = []
    for path, operations in before["paths"].items():
        for method, old in operations.items():
            where = f"{method.upper()} {path}"
            new = after["paths"].get(path, {}).get(method)
            if new is None:
                found.append(f"{where}: gone")
                continue
            parameters = {(p["name"], p["in"]): p for p in new.get("parameters", [])}
            for p in old.get("parameters", []):
                if (p["name"], p["in"]) not in parameters:
                    found.append(f"{where} {p['in']} {p['name']}: gone")
                else:
                    found += changes(before, after, p["schema"], parameters[p["name"], p["in"]]["schema"], f"{where} {p['name']}", True)
            for kind, body in old.get("requestBody", {}).get("content", {}).items():
                other = new.get("requestBody", {}).get("content", {}).get(kind)
                if other is None:
                    found.append(f"{where} body {kind}: gone")
                else:
                    found += changes(before, after, body["schema"], other["schema"], where, True)
            for status, answer in old["responses"].items():
                kinds = new["responses"].get(status, {}).get("content", {}) if status in new["responses"] else None
                if kinds is None:
                    found.append(f"{where} {status}: gone")
                    continue
                for kind, body in answer.get("content", {}).items():
                    if kind not in kinds:
                        found.append(f"{where} {status} {kind}: gone")
                    elif "schema" in body:
                        found += changes(before, after, body["schema"], kinds[kind].get("schema", {}), f"{where} {status}", False)
    return found


@pytest.fixture(scope="module")
def schema():
    return create_app().openapi()


def test_every_path_and_field_of_the_released_schema_answers_as_before(schema):
    assert [d for d in differences(json.loads(RELEASED.read_text()), schema) if d not in CORRECTED] == []


def test_the_corrections_are_what_the_server_answers():
    """Each correction of the released schema (:data:`CORRECTED`) is one the comparison sees, and the server's answer
    is what the corrected schema says."""
    from exprclone import data as samples

    assert set(CORRECTED) <= set(differences(json.loads(RELEASED.read_text()), create_app().openapi()))
    client = TestClient(create_app())  # (outside a with block: no worker is started)
    photo, video = client.get("/api/samples/portrait"), client.get("/api/samples/driving_video")
    assert (photo.headers["content-type"], video.headers["content-type"]) == ("image/jpeg", "video/mp4")
    assert photo.content == samples.path(samples.TARGET).read_bytes()


@pytest.mark.parametrize(
    "change, said",
    [
        (lambda s: s["paths"].pop("/api/faces"), "POST /api/faces: gone"),
        (lambda s: s["components"]["schemas"]["FacesFound"]["properties"].pop("width"), "POST /api/faces 200.width: gone"),
        (lambda s: s["components"]["schemas"]["FacesFound"]["required"].remove("width"), "no longer promises ['width']"),
        (lambda s: s["components"]["schemas"]["Body_clone_api_clone_post"]["required"].append("method"), "newly required ['method']"),
        (lambda s: s["components"]["schemas"]["Body_clone_api_clone_post"]["properties"]["method"]["enum"].pop(), "no longer takes"),
        (lambda s: s["paths"]["/api/clone"]["post"]["parameters"].pop(0), "POST /api/clone query format: gone"),
        (lambda s: s["components"]["schemas"]["JobState"]["properties"]["progress"].update(type="string"), "type ['number']"),
    ],
)
def test_the_comparison_sees_a_change_a_client_would_see(schema, change, said):
    changed = copy.deepcopy(schema)
    change(changed)
    assert any(said in d for d in differences(schema, changed)), differences(schema, changed)


def form_fields(schema: dict, path: str) -> dict:
    """The form fields of a route's body, by key."""
    body = schema["paths"][path]["post"]["requestBody"]["content"]["multipart/form-data"]["schema"]
    return resolve(schema, body)["properties"]


@pytest.fixture(scope="module")
def answer():
    found = TestClient(create_app()).get("/api/options")  # (outside a with block: no worker is started)
    assert found.status_code == 200
    return {o["key"]: o for o in found.json()["options"]}


def test_the_options_answer_says_what_the_schema_says_of_each_form_field(schema, answer):
    """Each option offered to forms, described by ``GET /api/options`` as its form field is in the schema: its JSON type,
    choices, bounds, pattern, default and help."""
    fields = {**form_fields(schema, "/api/clone"), **form_fields(schema, "/api/video")}
    for cls in VALUES:
        for name in offered(cls, "form"):
            described, field = answer[key(cls, name)], fields[key(cls, name)]
            if described["file"]:
                continue
            assert described["kind"] == field["type"] and described["choices"] == field.get("enum"), name
            assert (described["minimum"], described["maximum"]) == (field.get("minimum"), field.get("maximum")), name
            assert described["pattern"] == field.get("pattern") and described["default"] == field.get("default"), name
            assert field["description"].startswith(described["help"]), name
    assert set(answer) == {key(c, n) for c in VALUES for n in names(c) if spec(c, n).surfaces}


def test_the_options_answer_offers_the_methods_and_lambdas_in_words(answer):
    """The methods with their panel letters (a to g, as Fig. 11; Song et al.'s none), the lambdas the DB metric searches,
    the strengths' range, every choice with a label."""
    from exprclone.geometry.db_metric import LAMBDAS
    from exprclone.methods import TABLE

    methods = answer["method"]["page"]["choices"]
    assert [(c["value"], c["panel"]) for c in methods] == [(m.name, m.panel or None) for m in TABLE] and all(c["sentence"] for c in methods)
    lambdas = [c["value"] for c in answer["lambda"]["page"]["choices"]]
    assert lambdas == ["auto", *(f"{lam:g}" for lam in LAMBDAS)] and lambdas[-1] == "inf"
    assert (answer["strength"]["minimum"], answer["strength"]["maximum"], answer["strength"]["default"]) == (0, 2, 1)
    assert answer["strength_mouth"]["page"]["follows"] == "strength" and answer["strength_mouth"]["render"]
    assert answer["mouth"]["flag"] == "--no-mouth" and answer["mouth"]["flag_help"].startswith("paste no mouth interior")
