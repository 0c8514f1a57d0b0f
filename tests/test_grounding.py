"""catc ground: grounding annotations checked by catc check, artifacts of the paper's examples
(golden files, and every file read back by the rules of the program that reads it), the diff
between two compositions, and hostile text.

The golden files pin determinism (regenerate with `python tests/test_grounding.py`); what they
must contain is checked independently below: by the readers in tests/grounding_checks.py and
by facts derived by hand from each example's model and expect.toml."""

from __future__ import annotations

import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import yaml
from conftest import ROOT, run_catc
from grounding_checks import bt_errors, bt_loads_in_btcpp, compose_errors, rcl_params

EX = ROOT / "examples"
GOLDEN = ROOT / "tests" / "golden" / "grounding"
CASES = ["detection/person", "search-and-rescue/event1-fresh", "search-and-rescue/event2-out-of-range",
         "search-and-rescue/event4-dark"]  # fmt: skip
FILES = ("instructions.md", "compose.yaml", ".env", "params.yaml", "bt.xml", "manifest.json")


def ground(case: str, out: Path, *extra: str):
    return run_catc("ground", str(EX / f"{case}.cat"), "-o", str(out), *extra)


# ---------------------------------------------------------------- the examples


@pytest.mark.parametrize("case", CASES)
def test_every_artifact_is_written_as_recorded(case, tmp_path):
    res = ground(case, tmp_path)
    assert res.exit_code == 0, res.output
    for name in FILES:
        assert (tmp_path / name).read_bytes() == (GOLDEN / case.replace("/", "_") / name).read_bytes(), name


@pytest.mark.parametrize("case", CASES)
def test_every_artifact_reads_back_by_its_readers_rules(case, tmp_path):
    assert ground(case, tmp_path).exit_code == 0
    text = {name: (tmp_path / name).read_text(encoding="utf-8") for name in FILES}
    assert compose_errors(text["compose.yaml"]) == []
    params = rcl_params(text["params.yaml"])
    assert bt_errors(text["bt.xml"]) == []
    bt_loads_in_btcpp(text["bt.xml"])
    manifest = json.loads(text["manifest.json"])
    import hashlib

    for name in FILES[:-1]:
        assert manifest["artifacts"][name]["sha256"] == hashlib.sha256((tmp_path / name).read_bytes()).hexdigest()
    compose = yaml.safe_load(text["compose.yaml"])
    nodes = {
        a.split(":=")[1] for s in compose["services"].values() for a in s.get("command", []) if a.startswith("__node:=")
    }
    assert {n.removeprefix("/**/") for n in params} == nodes  # every node has its parameters


def test_detection_grounds_to_what_its_model_says():
    """By hand from examples/detection: mount the camera (one hardware step), run the driver
    on image-raw with 0.5 GB (the least RAM, expect.toml) and the detector asked for person."""
    case = GOLDEN / "detection_person"
    compose = yaml.safe_load((case / "compose.yaml").read_text())
    assert set(compose["services"]) == {"camera-driver", "open-vocab-detector"}
    assert compose["services"]["camera-driver"]["profiles"] == ["drivers"]
    assert compose["services"]["open-vocab-detector"]["profiles"] == ["skillsets"]
    assert "image:=image_raw" in compose["services"]["open-vocab-detector"]["command"]
    params = rcl_params((case / "params.yaml").read_text())
    assert params["/**/usb_cam"] == {"memory_limit_gb": 0.5, "frame_rate": 30}
    assert params["/**/detector"] == {"classes": "person", "score_threshold": 0.5}
    lines = (case / "instructions.md").read_text().splitlines()
    assert sum(line[:2] == "1." for line in lines) == 1 and "Mount the RGB camera" in lines[4]


@pytest.mark.parametrize("case", CASES[1:])
def test_sar_artifacts_follow_the_composition(case):
    """Hardware steps are the composition's hardware morphisms in plan order, services its
    software morphisms (and the executor), tree nodes its behaviours in plan order."""
    from catc.api import load

    manifest = json.loads((GOLDEN / case.replace("/", "_") / "manifest.json").read_text())
    model = load(EX / f"{case}.cat")
    morphisms = model.instance.morphisms
    used = [a["morphism"] for step in manifest["plan"]["steps"] for a in step]
    kinds = {m: morphisms[m].kind.value for m in used}
    instructions = (GOLDEN / case.replace("/", "_") / "instructions.md").read_text()
    hardware = [m for m in used if kinds[m] == "hardware"]
    assert [line.split("**")[1] for line in instructions.splitlines() if "**" in line] == hardware
    compose = yaml.safe_load((GOLDEN / case.replace("/", "_") / "compose.yaml").read_text())
    assert set(compose["services"]) == {m for m in used if kinds[m] == "software"} | {"bt-executor"}
    tree = ET.fromstring((GOLDEN / case.replace("/", "_") / "bt.xml").read_text())
    ids = [node.tag for node in tree.find("BehaviorTree").iter() if node.tag not in ("BehaviorTree", "Sequence")]
    assert ids == [morphisms[m].grounding.node_id for m in used if kinds[m] == "behavior"]


def test_event_ii_grounds_the_optimum():
    """Event II has a metric: catc ground deploys the optimum, moving back exactly 4 m
    (search-and-rescue/expect.toml)."""
    tree = ET.fromstring((GOLDEN / "search-and-rescue_event2-out-of-range" / "bt.xml").read_text())
    assert tree.find(".//ReturnToRange").get("distance") == "4"


def test_grounding_is_deterministic(tmp_path):
    assert ground(CASES[1], tmp_path / "a").exit_code == ground(CASES[1], tmp_path / "b").exit_code == 0
    for name in FILES:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_a_given_plan_is_grounded_and_an_invalid_one_refused(tmp_path):
    doc = json.loads(run_catc("solve", str(EX / "detection/person.cat"), "--json").stdout)
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"schema": "catc.plan/1", "steps": doc["steps"], "fresh": doc["fresh"]}))
    assert ground("detection/person", tmp_path / "out", "--plan", str(plan)).exit_code == 0
    plan.write_text(
        json.dumps({"steps": [[{"morphism": "camera-driver", "params": {"out": "image-raw", "ram-req": 1}}]]})
    )
    res = ground("detection/person", tmp_path / "bad", "--plan", str(plan))
    assert res.exit_code == 1 and "precondition" in res.stderr and not (tmp_path / "bad").exists()


def test_the_documented_artifacts_are_the_files():
    """docs/grounding.md shows artifacts under <!-- golden: CASE/FILE --> markers: each block
    must be the golden file, byte for byte (so the documentation cannot go stale)."""
    import re

    doc = (ROOT / "docs" / "grounding.md").read_text()
    blocks = re.findall(r"<!-- golden: (\S+) -->\n```\w*\n(.*?)```\n", doc, re.DOTALL)
    assert len(blocks) >= 5
    for name, text in blocks:
        assert text == (GOLDEN / name).read_text(), name


# ---------------------------------------------------------------- missing annotations


def test_a_morphism_without_grounding_is_named_never_skipped(tmp_path):
    res = run_catc("ground", str(EX / "lifelong/cheaper-camera.cat"), "-o", str(tmp_path / "out"))
    assert res.exit_code == 0 and "warning[W0106]: morphism 'buy-lidar' has no (:ground ...)" in res.stderr
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert "buy-lidar" in manifest["missing_grounding"]
    res = run_catc("ground", str(EX / "lifelong/cheaper-camera.cat"), "-o", str(tmp_path / "strict"), "--strict")
    assert res.exit_code == 2 and "error[W0106]" in res.stderr and not (tmp_path / "strict").exists()


# ---------------------------------------------------------------- the diff


def _plan_file(path: Path, steps: list) -> Path:
    path.write_text(json.dumps({"schema": "catc.plan/1", "steps": steps, "fresh": {}}))
    return path


def test_the_diff_lists_exactly_the_churn_of_a_recomposition(tmp_path):
    """Objective-first recomposition of the lifelong example (lifelong/expect.toml: churn 4,
    buy-camera-lite and inspect-lite for buy-camera and inspect): the diff from the deployed
    composition to the recomposed one names exactly those components."""
    model_file = str(EX / "lifelong/cheaper-camera.cat")
    old = json.loads(run_catc("recompose", model_file, "--json").stdout)  # stability first: the deployed one
    assert old["churn"] == 0
    new = json.loads(run_catc("recompose", model_file, "--priority", "objective", "--json").stdout)
    assert sorted(c["morphism"] for c in new["changes"]) == ["buy-camera", "buy-camera-lite", "inspect", "inspect-lite"]
    a, b = _plan_file(tmp_path / "old.json", old["steps"]), _plan_file(tmp_path / "new.json", new["steps"])
    res = run_catc("ground", model_file, "--diff", str(a), str(b), "--json")
    diff = json.loads(res.stdout)
    added = sorted(c["morphism"] for c in new["changes"] if c["change"] == "added")
    removed = sorted(c["morphism"] for c in new["changes"] if c["change"] == "removed")
    assert diff["schema"] == "catc.ground-diff/1" and diff["added"] == added and diff["removed"] == removed
    assert res.stderr.count("warning[W0106]") == len({a["morphism"] for s in old["steps"] + new["steps"] for a in s})


def test_the_sar_diff_for_the_cheaper_camera(tmp_path):
    """SAR: event I's composition (deployed in cheaper-camera.cat) against the one the file's
    comment derives by hand for objective first — the lite camera and its driver instead of
    the RGB camera and its driver (churn 4; `catc recompose --priority objective` answers the
    same, but takes minutes on SAR, so the lifelong test above runs the query itself).  On the robot: unmount one camera, mount the
    other, stop one driver service and start the other; the behaviour tree is unchanged."""
    model_file = str(EX / "search-and-rescue/cheaper-camera.cat")
    old = json.loads(run_catc("recompose", model_file, "--json").stdout)  # stability first: churn 0, as deployed
    assert old["churn"] == 0
    swap = {"mount-rgb-camera": "mount-rgb-camera-lite", "rgb-driver": "rgb-lite-driver"}
    new_steps = [[{"morphism": swap.get(a["morphism"], a["morphism"]),
                   "params": {} if a["morphism"] in swap else a["params"]} for a in step] for step in old["steps"]]  # fmt: skip
    a, b = _plan_file(tmp_path / "old.json", old["steps"]), _plan_file(tmp_path / "new.json", new_steps)
    diff = json.loads(run_catc("ground", model_file, "--diff", str(a), str(b), "--json").stdout)
    assert diff["added"] == ["mount-rgb-camera-lite", "rgb-lite-driver"]
    assert diff["removed"] == ["mount-rgb-camera", "rgb-driver"]
    assert diff["unmount"] == ["mount-rgb-camera"] and diff["mount"] == ["mount-rgb-camera-lite"]
    assert diff["stop"] == ["rgb-driver"] and diff["start"] == ["rgb-lite-driver"] and not diff["tree_changed"]
    text = run_catc("ground", model_file, "--diff", str(a), str(b)).stdout
    assert (
        "docker compose -p search-and-rescue -f compose.yaml --profile drivers --profile skillsets --profile "
        "executors up -d --remove-orphans"
    ) in text  # every profile in use is activated: a service in an inactive profile is not started


def _grounded_of(case: str):
    """The resolved grounding of a golden case's composition (its manifest's plan)."""
    from catc.api import load
    from catc.queries.validate import param_sorts
    from catc.semantics.plan import plan_from_json
    from catc.targets.grounding.resolve import ground

    model = load(EX / f"{case}.cat")
    manifest = json.loads((GOLDEN / case.replace("/", "_") / "manifest.json").read_text())
    plan = plan_from_json(manifest["plan"], param_sorts(model.instance))
    return ground(model.instance, plan, model.validate(plan).report.states)


@pytest.mark.parametrize(
    "old, new", [(CASES[1], CASES[2]), (CASES[1], CASES[3]), (CASES[3], CASES[2]), (CASES[2], CASES[2])]
)
def test_the_diff_of_written_artifacts_is_the_diff_of_the_compositions(old, new):
    """A runtime diffs what it has on disk (diff_artifacts); catc ground --diff diffs two
    compositions (ground_diff).  On every pair of the SAR events they must agree."""
    from catc.targets.grounding.diff import diff_artifacts, ground_diff

    files = [{n: (GOLDEN / c.replace("/", "_") / n).read_bytes() for n in FILES} for c in (old, new)]
    by_files = diff_artifacts(files[0], files[1])
    by_plans = ground_diff(_grounded_of(old), _grounded_of(new))
    assert by_files == by_plans
    assert by_files.empty if old == new else True
    if {old, new} == {CASES[1], CASES[2]}:  # event II adds return-to-range, a behaviour: the tree changes
        assert by_files.tree_changed and "return-to-range" in by_files.added + by_files.removed


# ---------------------------------------------------------------- annotations checked


DOMAIN = """(define (domain g)
  (:requirements :numeric :sets :free-parameters :grounding)
  (:sorts topic slot - symbol)
  (:constants image-raw - topic s1 s2 - slot)
  (:resources (ram real) (topics (set topic)) (mounted bool))
  (:morphism mount-cam :kind hardware :uses 1 :parameters ((where slot)) :effect (assign mounted true)
    :ground GROUND_HW)
  (:morphism cam-driver :kind software :uses 1 :parameters ((out topic) (mem real :bounds (0.5 2)))
    :precondition (and mounted (>= ram mem)) :effect (and (add topics out) (decrease ram mem))
    :ground GROUND_SW)
  (:morphism explore :kind behavior :uses 1 :parameters ((t topic)) :precondition (member t topics)
    :ground GROUND_BT)
  DEPLOYMENT)
"""
GOOD = {
    "GROUND_HW": '(hardware :instruction "Mount the camera on rail slot {where}" :check "LED {{on}}")',
    "GROUND_SW": '(software :image "ghcr.io/acme/usb-cam:1.0" :params ((memory mem) (fps 30)) :remap (("image_raw" out)))',
    "GROUND_BT": "(behavior :id Explore :inputs ((topic t)) :outputs ((found (key victim_pose))))",
    "DEPLOYMENT": '(:deployment :project rescue :executor "ghcr.io/acme/bt:2")',
}


def check(tmp_path: Path, **changes: str):
    text = DOMAIN
    for key, value in {**GOOD, **changes}.items():
        text = text.replace(key, value)
    (tmp_path / "g.cat").write_text(text)
    return run_catc("check", str(tmp_path / "g.cat"))


def test_well_formed_annotations_check_clean(tmp_path):
    res = check(tmp_path)
    assert res.exit_code == 0, res.output


@pytest.mark.parametrize(
    "change, code, words",
    [
        ({"GROUND_HW": '(software :image "a:1")'}, "E0508", "is hardware, but its grounding is software"),
        ({"GROUND_HW": '(hardwar :instruction "x")'}, "E0508", "did you mean 'hardware'"),
        ({"GROUND_HW": '(hardware :instruction "slot {slto}")'}, "E0508", "{slto} names no parameter"),
        ({"GROUND_HW": '(hardware :instruction "a lone { brace")'}, "E0508", "a lone '{'"),
        ({"GROUND_HW": '(hardware :check "x")'}, "E0508", "needs :instruction"),
        ({"GROUND_HW": '(hardware :instruction "x" :imgae "y")'}, "E0508", "':imgae' does not belong"),
        ({"GROUND_HW": '(hardware :instruction "x" :instruction "y")'}, "E0205", "given twice"),
        ({"GROUND_SW": "(software :params ((fps 30)))"}, "E0508", "needs :image"),
        ({"GROUND_SW": '(software :image "Bad/Image")'}, "E0509", "cannot be a container image"),
        ({"GROUND_SW": '(software :image "a:1" :node "9node")'}, "E0509", "cannot be a ROS 2 node name"),
        ({"GROUND_SW": '(software :image "a:1" :params ((bad-name 1)))'}, "E0509", "cannot be a name in :params"),
        ({"GROUND_SW": '(software :image "a:1" :params ((x rma)))'}, "E0202", "did you mean 'ram'"),
        ({"GROUND_SW": '(software :image "a:1" :remap (("bad topic" out)))'}, "E0509", "cannot be a topic name"),
        ({"GROUND_SW": '(software :image "a:1" :remap (("t" 3)))'}, "E0508", "a remapping's target is a topic"),
        ({"GROUND_SW": '(software :image "a:1" :profile driver)'}, "E0508", "did you mean 'drivers'"),
        ({"GROUND_SW": '(software :image "a:1" :params ((p (key k))))'}, "E0508", "belong to behaviour ports"),
        ({"GROUND_BT": "(behavior :id 3x)"}, "E0107", "malformed number"),
        ({"GROUND_BT": '(behavior :id "xml-id")'}, "E0509", "cannot be a BehaviorTree.CPP node ID"),
        ({"GROUND_BT": "(behavior :id E :outputs ((found 3)))"}, "E0508", "writes a blackboard entry"),
        ({"GROUND_BT": '(behavior :id E :inputs (("bad port" t)))'}, "E0509", "cannot be a name in :inputs"),
        ({"DEPLOYMENT": "(:deployment :project Rescue)"}, "E0509", "cannot name a Compose project"),
        ({"DEPLOYMENT": '(:deployment :executor "a:1")'}, "E0508", "needs :project"),
    ],
)
def test_every_rule_has_a_located_error(tmp_path, change, code, words):
    res = check(tmp_path, **change)
    assert res.exit_code in (1, 2), res.output
    assert f"error[{code}]" in res.stdout and words in res.stdout, res.stdout
    assert "g.cat:" in res.stdout.split(f"error[{code}]")[0].splitlines()[-1]  # located in the file


def test_grounding_needs_its_requirement(tmp_path):
    text = DOMAIN.replace(" :grounding)", ")")
    for key, value in GOOD.items():
        text = text.replace(key, value)
    (tmp_path / "g.cat").write_text(text)
    res = run_catc("check", str(tmp_path / "g.cat"))
    assert res.exit_code == 1 and "error[E0401]" in res.stdout and "':grounding'" in res.stdout


def test_two_components_cannot_be_one_node(tmp_path):
    """Two drivers that both say :node cam may be alternatives (fine) but not run together:
    the ROS 2 graph would have two nodes named cam and params.yaml one entry for both."""
    (tmp_path / "d.cat").write_text("""(define (domain two)
  (:requirements :numeric :grounding)
  (:resources (a bool) (b bool))
  (:morphism left :kind software :uses 1 :effect (assign a true)
    :ground (software :image "x/left:1" :node cam))
  (:morphism right :kind software :uses 1 :effect (assign b true)
    :ground (software :image "x/right:1" :node cam)))
(define (problem p) (:domain two) (:init (= a false) (= b false)) (:goal (and a b)))
""")
    assert run_catc("check", str(tmp_path / "d.cat")).exit_code == 0  # each alone is fine
    res = run_catc("ground", str(tmp_path / "d.cat"), "-o", str(tmp_path / "out"))
    assert res.exit_code == 2 and not (tmp_path / "out").exists()
    first = res.stderr.splitlines()[0]
    assert "d.cat:7:13: error[E0508]" in first and "two ROS 2 nodes named 'cam' (left and right)" in first
    assert "note: " in res.stderr and "d.cat:5:13: the other one" in res.stderr
    res = run_catc("ground", str(tmp_path / "d.cat"), "-o", str(tmp_path / "out"), "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 2 and doc["schema"] == "catc.error/1" and doc["diagnostics"][0]["code"] == "E0508"


def test_behaviours_of_one_step_run_in_parallel(tmp_path):
    """Two behaviours activated in one step (⊗) are one Parallel node that succeeds when both
    do, between the steps before and after it in the Sequence."""
    (tmp_path / "d.cat").write_text("""(define (domain par)
  (:requirements :numeric :grounding)
  (:resources (a bool) (b bool) (c bool))
  (:morphism look :kind behavior :uses 1 :effect (assign a true)
    :ground (behavior :id Look :outputs ((seen (key seen)))))
  (:morphism listen :kind behavior :uses 1 :effect (assign b true)
    :ground (behavior :id Listen :outputs ((heard (key heard)))))
  (:morphism tell :kind behavior :uses 1 :precondition (and a b) :effect (assign c true)
    :ground (behavior :id Tell :inputs ((what (key heard)) (where (key seen))))))
(define (problem p) (:domain par) (:init (= a false) (= b false) (= c false)) (:goal c))
""")
    plan = _plan_file(tmp_path / "plan.json", [[{"morphism": "look", "params": {}}, {"morphism": "listen", "params": {}}],
                                               [{"morphism": "tell", "params": {}}]])  # fmt: skip
    res = run_catc("ground", str(tmp_path / "d.cat"), "-o", str(tmp_path / "out"), "--plan", str(plan))
    assert res.exit_code == 0, res.output
    text = (tmp_path / "out" / "bt.xml").read_text()
    assert bt_errors(text) == []
    bt_loads_in_btcpp(text)
    sequence = ET.fromstring(text).find("BehaviorTree/Sequence")
    assert [child.tag for child in sequence] == ["Parallel", "Tell"]
    parallel = sequence[0]
    assert [child.tag for child in parallel] == ["Look", "Listen"] and parallel.get("success_count") == "2"


# ---------------------------------------------------------------- hostile text

HOSTILE = ['say \\"hi\\"', "<tag> & </tag>", "{not a key}", "yes", "y", "010", "1e3", "--ros-args", "a: b", "#c"]


@pytest.mark.parametrize("text", HOSTILE)
def test_no_model_text_reaches_an_artifact_unescaped(tmp_path, text):
    """Strings of the model land in YAML and XML as the same strings, never as structure."""
    unquoted = text.replace('\\"', '"')
    changes = {
        "GROUND_HW": f'(hardware :instruction "{text.replace("{", "{{").replace("}", "}}")}")',  # a template
        "GROUND_SW": f'(software :image "ghcr.io/a/b:1" :params ((label "{text}")))',
        "GROUND_BT": f'(behavior :id Explore :inputs ((note "{text}")) :outputs ((found (key pose))))',
    }
    assert check(tmp_path, **changes).exit_code == 0
    (tmp_path / "p.cat").write_text(
        "(define (problem p) (:domain g) (:init (= ram 4)) (:goal (member image-raw topics)))"
    )
    out = tmp_path / "out"
    plan = _plan_file(tmp_path / "plan.json", [[{"morphism": "mount-cam", "params": {"where": "s1"}}],
                                               [{"morphism": "cam-driver", "params": {"out": "image-raw", "mem": 1}}],
                                               [{"morphism": "explore", "params": {"t": "image-raw"}}]])  # fmt: skip
    res = run_catc("ground", str(tmp_path / "g.cat"), str(tmp_path / "p.cat"), "-o", str(out), "--plan", str(plan))
    assert res.exit_code == 0, res.output
    assert rcl_params((out / "params.yaml").read_text())["/**/cam_driver"]["label"] == unquoted
    compose = yaml.safe_load((out / "compose.yaml").read_text())
    assert compose_errors((out / "compose.yaml").read_text()) == [] and len(compose["services"]) == 2
    tree = ET.fromstring((out / "bt.xml").read_text())
    assert tree.find(".//Explore").get("note") == unquoted
    bt_loads_in_btcpp((out / "bt.xml").read_text())
    assert unquoted in (out / "instructions.md").read_text().replace("\\", "")


if __name__ == "__main__":  # regenerate the golden files (then read the diff before committing)
    import shutil
    import subprocess

    for case in CASES:
        target = GOLDEN / case.replace("/", "_")
        shutil.rmtree(target, ignore_errors=True)
        subprocess.run([sys.executable, "-m", "catc", "ground", str(EX / f"{case}.cat"), "-o", str(target)], check=True)
