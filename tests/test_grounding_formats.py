"""The grounding writers against the rules of the programs that read their files (the
checkers in tests/grounding_checks.py are written from rcl's, the compose-spec's and
BehaviorTree.CPP's rules, independently of the writers), and the checkers themselves
against files those programs refuse."""

from __future__ import annotations

from fractions import Fraction

import pytest
import yaml
from grounding_checks import (
    RclError,
    bt_errors,
    bt_loads_in_btcpp,
    compose_errors,
    rcl_params,
    rcl_value,
    real_rcl_checker,
    real_rcl_params,
    reimplemented_rcl_params,
)

from catc.ir.grounding import Profile
from catc.semantics.plan import Activation, Plan
from catc.targets.grounding.bt import bt_xml
from catc.targets.grounding.compose import compose_env, compose_yaml
from catc.targets.grounding.diff import ground_diff
from catc.targets.grounding.params import params_yaml
from catc.targets.grounding.resolve import BehaviorNode, Grounded, HardwareStep, Key, Real, Service
from catc.targets.grounding.yamlio import dump, float_text, typed_as_non_string

HOSTILE = ['say "hi"', "a\nb", "<tag>", "a & b", "{not a key}", "yes", "y", "N", "on", "010", "0x1F", "1e3", "inf",
           "nan", "~", "null", "", " padded ", "- dash", "#hash", "key: value", "'quote'"]  # fmt: skip


def grounded(**over) -> Grounded:
    fields = {
        "project": "rescue",
        "hardware": (HardwareStep(1, "mount-camera", "Mount the camera on slot 2", "LED is green", ("M3 screws",)),),
        "services": (
            Service("camera-driver", "camera-driver", "ghcr.io/acme/usb-cam:1.0", "camera_driver", Profile.DRIVERS,
                    (("memory_gb", Real(Fraction(1, 2))), ("fps", 30), ("rate", Real(Fraction(50))),
                     ("label", "yes"), ("classes", ["person", "dog"])), (("image_raw", "camera/image"),)),
            Service("bt-executor", None, "ghcr.io/acme/bt:2", None, Profile.EXECUTORS),
        ),
        "behaviours": (
            (BehaviorNode("explore", "Explore", (("area", "lab"),), (("found", "{victim}"),)),),
            (BehaviorNode("approach", "Approach", (("target", "{victim}"),), ()),
             BehaviorNode("speak", "Speak", (("text", "hello"),), ())),
        ),
        "missing": (),
        "plan": Plan([[Activation("mount-camera")], [Activation("camera-driver")]]),
    }  # fmt: skip
    fields.update(over)
    return Grounded(**fields)


# ---------------------------------------------------------------- params.yaml


def test_params_read_by_rcl_with_their_types():
    params = rcl_params(params_yaml(grounded()))
    assert params == {
        "/**/camera_driver": {
            "memory_gb": 0.5,
            "fps": 30,
            "rate": 50.0,  # a real: a double, written 50.0
            "label": "yes",  # a string rcl would have read as true: quoted
            "classes": ["person", "dog"],
        }
    }
    assert isinstance(params["/**/camera_driver"]["rate"], float)
    assert isinstance(params["/**/camera_driver"]["fps"], int)


@pytest.mark.parametrize("text", HOSTILE)
def test_strings_come_back_as_the_same_strings(text):
    doc = params_yaml(grounded(services=(Service("s", "s", "i:1", "n", Profile.DRIVERS, (("p", text),)),)))
    assert rcl_params(doc) == {"/**/n": {"p": text}}
    assert yaml.safe_load(doc)["/**"]["n"]["ros__parameters"]["p"] == text


def test_no_aliases_even_for_shared_objects():
    shared = ["a", "b"]
    text = dump({"one": shared, "two": shared})
    assert "&" not in text and "*" not in text and yaml.safe_load(text) == {"one": shared, "two": shared}


@pytest.mark.parametrize(
    "value, text",
    [
        (Fraction(50), "50.0"),
        (Fraction(17, 4), "4.25"),
        (Fraction(-1, 8), "-0.125"),
        (Fraction(1, 3), "0.3333333333333333"),
    ],
)
def test_reals_are_floats_exact_where_a_decimal_is(value, text):
    assert float_text(value) == text
    assert rcl_value(text, False) == float(value)


def test_what_rcl_types_is_quoted():
    for text in ["y", "Y", "n", "yes", "on", "OFF", "010", "0x1F", "12", "1e3", "inf", "-nan", ".inf", "1.5"]:
        assert typed_as_non_string(text), text
        assert not isinstance(rcl_value(text, False), str), text
    for text in ["camera_driver", "image_raw", "yesno", "0x", "1e", "person"]:
        assert not typed_as_non_string(text), text


@pytest.mark.parametrize(
    "text, complaint",
    [
        ("/**:\n  n:\n    ros__parameters:\n      a: &x 1\n      b: *x\n", "alias"),
        ("/**:\n  9lives:\n    ros__parameters:\n      a: 1\n", "invalid node name"),
        ("/**:\n  bad-name:\n    ros__parameters:\n      a: 1\n", "invalid node name"),
        ("ros__parameters:\n  a: 1\n", "no node names"),
        ("/**:\n  n:\n    ros__parameters:\n      a: [1, x]\n", "same type"),
        ("/**:\n  n:\n    ros__parameters:\n      a:\n", "No value"),
        ("/**:\n  n: 3\n", "Cannot have a value before ros__parameters"),
    ],
)
def test_the_rcl_checker_refuses_what_rcl_refuses(text, complaint):
    with pytest.raises(RclError, match=complaint):
        reimplemented_rcl_params(text)
    real = real_rcl_checker()
    if real is not None:  # the real parser refuses them too (in its own words)
        with pytest.raises(RclError):
            real_rcl_params(text, real)


def test_rclcpp_refuses_an_empty_list_which_rcl_parses():
    """rcl reads ``[]`` as a parameter with no value; rclcpp's parameter_value_from throws
    "No parameter value set", so a node given the file does not start."""
    real = real_rcl_checker()
    if real is None:
        pytest.skip("the real rcl parser could not be built here (gcc, libyaml-dev, shared/tools)")
    with pytest.raises(RclError, match="No parameter value set"):
        real_rcl_params("/**:\n  n:\n    ros__parameters:\n      a: []\n", real)


def test_the_rcl_checker_types_values_as_rcl_does():
    assert rcl_value("010", False) == 8 and rcl_value("0x10", False) == 16 and rcl_value("08", False) == 8.0
    assert rcl_value("y", False) is True and rcl_value("'y'", True) == "'y'" and rcl_value("y", True) == "y"
    assert rcl_value("1e3", False) == 1000.0 and rcl_value("abc", False) == "abc"


# ---------------------------------------------------------------- compose.yaml


def test_compose_passes_the_compose_spec_schema_and_our_checks():
    text = compose_yaml(grounded())
    assert compose_errors(text) == []
    doc = yaml.safe_load(text)
    driver = doc["services"]["camera-driver"]
    assert driver["profiles"] == ["drivers"] and "BT_FILE" not in driver["environment"]  # a driver runs no tree
    assert all("bt.xml" not in v for v in driver["volumes"])
    assert driver["command"][-2:] == ["-r", "image_raw:=camera/image"]
    executor = doc["services"]["bt-executor"]
    assert executor["profiles"] == ["executors"] and executor["environment"]["BT_FILE"] == "/catc/bt.xml"
    assert "./bt.xml:/catc/bt.xml:ro" in executor["volumes"]


def test_the_env_file_activates_exactly_the_profiles_in_use():
    assert compose_env(grounded()) == "COMPOSE_PROFILES=drivers,executors\n"
    only = grounded(services=(Service("s", "s", "i:1", "n", Profile.SKILLSETS),), behaviours=())
    assert compose_env(only) == "COMPOSE_PROFILES=skillsets\n"


def test_compose_checks_catch_what_the_schema_allows():
    bad = "services:\n  x:\n    image: ''\n    profiles: [other]\n"
    errors = compose_errors(bad)
    assert any("no image" in e for e in errors) and any("profiles" in e for e in errors)
    assert any("host" in e for e in errors) and any("PARAMS" in e for e in errors)
    assert compose_errors("services:\n  x:\n    image: a\n    netwrk_mode: host\n")  # the schema's own
    base = "services:\n  x:\n    image: a\n    network_mode: host\n    ipc: host\n    profiles: [drivers]\n"
    base += "    environment: {PARAMS: /p}\n"
    assert compose_errors(base + "    command: [--ros-args, --params-file, /p]\n")  # no __node:=
    assert compose_errors(base + "    command: [--ros-args, -r, __node:=n, --params-file, /p, -r]\n")
    assert compose_errors(base + "    command: [--ros-args, -r, __node:=n, --params-file, /p]\n") == []


# ---------------------------------------------------------------- bt.xml


def test_bt_is_well_formed_declared_and_loads_in_btcpp():
    text = bt_xml(grounded())
    assert bt_errors(text) == []
    bt_loads_in_btcpp(text)
    assert "<Parallel" in text and text.index("Explore") < text.index("Approach")


def test_bt_checker_catches_a_key_read_before_it_is_written():
    g = grounded(behaviours=((BehaviorNode("approach", "Approach", (("target", "{victim}"),), ()),),))
    assert any("reads {victim} before" in e for e in bt_errors(bt_xml(g)))


@pytest.mark.parametrize("text", HOSTILE)
def test_no_model_text_reaches_xml_unescaped(text):
    g = grounded(behaviours=((BehaviorNode("say", "Say", (("text", text),), ()),),))
    xml = bt_xml(g)
    bt_loads_in_btcpp(xml)
    import xml.etree.ElementTree as ET

    assert ET.fromstring(xml).find(".//Say").get("text") == text


def test_btcpp_refuses_what_is_not_a_tree():
    with pytest.raises(RuntimeError):
        bt_loads_in_btcpp("<root BTCPP_format='4'><BehaviorTree ID='X'><Sequence/><Sequence/></BehaviorTree></root>")


# ---------------------------------------------------------------- the diff


def test_the_diff_says_what_changes_on_the_robot():
    old = grounded()
    new_driver = Service("camera-driver", "camera-driver", "ghcr.io/acme/usb-cam:1.0", "camera_driver",
                         Profile.DRIVERS, (("fps", 15),))  # fmt: skip
    new = grounded(
        hardware=(HardwareStep(1, "mount-lite", "Mount the lite camera", None, ()),),
        services=(new_driver, Service("tracker", "tracker", "t:1", "tracker", Profile.SKILLSETS),
                  Service("bt-executor", None, "ghcr.io/acme/bt:2", None, Profile.EXECUTORS)),
        plan=Plan([[Activation("mount-lite")], [Activation("camera-driver"), Activation("tracker")]]),
    )  # fmt: skip
    d = ground_diff(old, new)
    assert d.added == ("mount-lite", "tracker") and d.removed == ("mount-camera",)
    assert d.unmount == ("mount-camera",) and d.mount == ("mount-lite",)
    assert d.start == ("tracker",) and d.stop == () and d.recreate == ("camera-driver",)
    assert not d.tree_changed
    assert ground_diff(old, old).empty
    assert d.commands()[-1][-1] == "camera-driver"


def test_keys_and_reals_as_port_text():
    from catc.targets.grounding.resolve import port_text

    assert port_text(Key("pose")) == "{pose}" and port_text(Real(Fraction(1, 3))) == "1/3"
    assert port_text(True) == "true" and port_text(["a", "b"]) == "a;b"
