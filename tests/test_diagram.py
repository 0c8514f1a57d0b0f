"""String diagrams of compositions (catc.present.diagram): structure of the SVG, not pixels."""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from fractions import Fraction

import pytest
from conftest import ROOT

from catc import ir
from catc.frontend.workspace import load_instance
from catc.present.diagram import format_value, render_svg
from catc.semantics.plan import Activation as A
from catc.semantics.plan import Plan
from catgrammar.diagnostics import Diagnostics

EX = ROOT / "examples"
NS = "{http://www.w3.org/2000/svg}"


def _load(path) -> ir.Instance:
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    return inst


@pytest.fixture(scope="module")
def detection() -> ir.Instance:
    return _load(EX / "detection" / "person.cat")


@pytest.fixture(scope="module")
def sar() -> ir.Instance:
    return _load(EX / "search-and-rescue" / "event1-fresh.cat")


@pytest.fixture(scope="module")
def gpu() -> ir.Instance:
    return _load(EX / "gpu-allocation" / "max-confidence.cat")


DETECTION_PLAN = Plan(
    [
        [A("mount-rgb-camera")],
        [A("camera-driver", {"out": "image-raw", "ram-req": Fraction(1)})],
        [A("open-vocab-detector", {"in": "image-raw", "target": "person"})],
    ]
)

# Event I by hand: every mount and every software component is alone in its step (they all
# update budget or ram, which the others read); behaviours run beside software.
SAR_PLAN = Plan(
    [
        [A("mount-external-battery")],
        [A("mount-lidar")],
        [A("mount-rgb-camera")],
        [A("mount-speaker-mic"), A("vlm")],
        [A("mount-long-range-radio")],
        [A("lidar-driver")],
        [A("rgb-driver", {"ram-req": Fraction(3, 4)})],
        [A("slam")],
        [A("open-vocab-detector", {"in": "rgb-image", "target": "person", "mem": Fraction(9, 2)}), A("explore")],
        [A("tracker")],
        [A("whisper-stt"), A("approach")],
        [A("tts")],
        [A("interact")],
        [A("report")],
    ]
)

GPU_PLAN = Plan([[A("slam")], [A("vlm")], [A("detector", {"m": Fraction(17, 4)})]])


# ---------------------------------------------------------------- helpers


def parse(svg: str) -> ET.Element:
    return ET.fromstring(svg)


def classes(el: ET.Element) -> set[str]:
    return set(el.get("class", "").split())


def having(root: ET.Element, *tokens: str) -> list[ET.Element]:
    return [el for el in root.iter() if set(tokens) <= classes(el)]


def texts(root: ET.Element) -> list[str]:
    return ["".join(el.itertext()) for el in root.iter(NS + "text")]


def boxes(root: ET.Element) -> list[ET.Element]:
    return having(root, "activation")


def rects(box: ET.Element) -> list[tuple[float, float, float, float]]:
    """(x0, y0, x1, y1) of each part of a box."""
    out = []
    for r in box.iter(NS + "rect"):
        if "morphism" in classes(r):
            x, y, w, h = (float(r.get(k)) for k in ("x", "y", "width", "height"))
            out.append((x, y, x + w, y + h))
    return out


def wire_ys(root: ET.Element) -> dict[str, float]:
    return {g.get("data-resource"): float(g.find(NS + "line").get("y1")) for g in having(root, "wire")}


# ---------------------------------------------------------------- the document


@pytest.mark.parametrize("which", ["detection", "sar", "gpu"])
def test_well_formed_svg_with_a_viewbox(which, request):
    inst = request.getfixturevalue(which)
    plan = {"detection": DETECTION_PLAN, "sar": SAR_PLAN, "gpu": GPU_PLAN}[which]
    root = parse(render_svg(inst, plan, title="t"))
    assert root.tag == NS + "svg"
    box = [float(v) for v in root.get("viewBox").split()]
    assert len(box) == 4 and box[2] > 0 and box[3] > 0
    assert float(root.get("width")) == box[2] and float(root.get("height")) == box[3]
    # nothing external: no scripts, images, links or imported fonts
    for el in root.iter():
        assert el.tag.removeprefix(NS) not in ("script", "image", "use", "foreignObject", "a", "style")
        assert not any("href" in k for k in el.attrib)
    # every drawn element lies inside the viewBox
    x0, y0, x1, y1 = box[0], box[1], box[0] + box[2], box[1] + box[3]
    for b in boxes(root):
        for rx0, ry0, rx1, ry1 in rects(b):
            assert x0 <= rx0 and rx1 <= x1 and y0 <= ry0 and ry1 <= y1


def test_every_morphism_and_theta_is_named(sar):
    root = parse(render_svg(sar, SAR_PLAN))
    names = [t for el in having(root, "morphism-name") for t in el.itertext()]
    assert sorted(names) == sorted(a.morphism for _, a in SAR_PLAN.activations)
    theta = " ".join("".join(el.itertext()) for el in having(root, "theta"))
    assert "ram-req=0.75" in theta and "in=rgb-image," in theta and "mem=4.5" in theta


def test_drawn_wires_are_exactly_the_resources_read_or_written(sar, detection):
    for inst, plan in ((sar, SAR_PLAN), (detection, DETECTION_PLAN)):
        root = parse(render_svg(inst, plan))
        used = set()
        for _, a in plan.activations:
            used |= inst.morphisms[a.morphism].reads | inst.morphisms[a.morphism].writes
        drawn = {g.get("data-resource") for g in having(root, "wire")}
        assert drawn == used
        labels = set(texts(root))
        for name in drawn:
            res = inst.resources[name]
            assert (f"{name} [{res.unit}]" if res.unit else name) in labels
    # without the detector, `detects` is untouched: omitted, and said so in the footnote
    root = parse(render_svg(detection, Plan(DETECTION_PLAN.steps[:2])))
    assert "detects" not in {g.get("data-resource") for g in having(root, "wire")}
    foot = " ".join("".join(el.itertext()) for el in having(root, "footnote"))
    assert "1 resource" in foot and "detects" in foot


def test_wires_are_grouped_in_group_order(sar):
    ys = wire_ys(parse(render_svg(sar, SAR_PLAN)))
    order = ["electromechanical", "compute", "info", "external"]
    ranked = sorted(ys, key=ys.__getitem__)
    groups = [sar.resources[r].group for r in ranked]
    assert groups == sorted(groups, key=order.index)
    # inside a group, declaration order
    declared = list(sar.resources)
    for g in order:
        inside = [r for r in ranked if sar.resources[r].group == g]
        assert inside == sorted(inside, key=declared.index)


# ---------------------------------------------------------------- ports


@pytest.mark.parametrize("which", ["detection", "sar", "gpu"])
def test_port_counts_match_the_ir(which, request):
    inst = request.getfixturevalue(which)
    plan = {"detection": DETECTION_PLAN, "sar": SAR_PLAN, "gpu": GPU_PLAN}[which]
    root = parse(render_svg(inst, plan))
    want_reads = sum(len(inst.morphisms[a.morphism].reads) for _, a in plan.activations)
    want_writes = sum(len(inst.morphisms[a.morphism].writes) for _, a in plan.activations)
    assert len(having(root, "port", "read")) == want_reads
    assert len(having(root, "port", "write")) == want_writes
    # per box: reads on the left edge, writes on the right edge, each on its own wire
    ys = wire_ys(root)
    for box in boxes(root):
        m = inst.morphisms[box.get("data-morphism")]
        parts = rects(box)
        left, right = parts[0][0], parts[0][2]
        reads = {c.get("data-resource"): c for c in having(box, "port", "read")}
        writes = {c.get("data-resource"): c for c in having(box, "port", "write")}
        assert set(reads) == m.reads and set(writes) == m.writes
        for r, c in reads.items():
            assert float(c.get("cx")) == pytest.approx(left, abs=0.15) and float(c.get("cy")) == ys[r]
            assert c.get("fill") == "#FFFFFF"  # hollow
        for r, c in writes.items():
            assert float(c.get("cx")) == pytest.approx(right, abs=0.15) and float(c.get("cy")) == ys[r]
            assert c.get("fill") != "#FFFFFF"  # filled
        # every touched wire lies inside one part of the box
        for r in m.reads | m.writes:
            assert any(y0 < ys[r] < y1 for _, y0, _, y1 in parts), (m.name, r)


def test_implicit_read_of_increase_is_no_read_port(sar):
    plan = Plan([[A("mount-external-battery")]])
    root = parse(render_svg(sar, plan))
    reads = {c.get("data-resource") for c in having(root, "port", "read")}
    writes = {c.get("data-resource") for c in having(root, "port", "write")}
    assert "power" not in reads and "power" in writes


# ---------------------------------------------------------------- geometry


def test_parallel_boxes_side_by_side_and_steps_in_order(sar):
    root = parse(render_svg(sar, SAR_PLAN))
    by_step: dict[int, list[ET.Element]] = {}
    for b in boxes(root):
        by_step.setdefault(int(b.get("data-step")), []).append(b)
    assert sorted(by_step) == list(range(1, len(SAR_PLAN.steps) + 1))
    assert [len(by_step[i + 1]) for i in range(len(SAR_PLAN.steps))] == [len(s) for s in SAR_PLAN.steps]
    spans = {}
    for step, bs in by_step.items():
        xs = sorted((rects(b)[0][0], rects(b)[0][2]) for b in bs)
        for (_, right), (left, _) in itertools.pairwise(xs):
            assert right < left, f"parallel boxes of step {step} overlap"
        spans[step] = (xs[0][0], xs[-1][1])
    for i in range(1, len(SAR_PLAN.steps)):
        assert spans[i][1] < spans[i + 1][0], f"step {i + 1} does not start after step {i}"
    headers = ["".join(el.itertext()) for el in having(root, "step-header")]
    assert headers[3] == "t=4 ⊗" and headers[0] == "t=1"


def test_untouched_wires_pass_over_dashed(gpu):
    root = parse(render_svg(gpu, GPU_PLAN))
    ys = wire_ys(root)
    for box in boxes(root):
        m = gpu.morphisms[box.get("data-morphism")]
        touched = m.reads | m.writes
        inside = {r for r, y in ys.items() for _, y0, _, y1 in rects(box) if y0 < y < y1}
        passing = {ln.get("data-resource") for ln in having(box, "passover")}
        assert passing == inside - touched
        assert all(ln.get("stroke-dasharray") for ln in having(box, "passover"))
    vlm = next(b for b in boxes(root) if b.get("data-morphism") == "vlm")
    assert {ln.get("data-resource") for ln in having(vlm, "passover")} == {"confidence", "slam-running"}


def test_long_runs_of_untouched_wires_break_the_box(sar):
    root = parse(render_svg(sar, SAR_PLAN))
    ys = wire_ys(root)
    mount = next(b for b in boxes(root) if b.get("data-morphism") == "mount-lidar")
    parts = rects(mount)
    assert len(parts) == 2  # electromechanical wires, and budget far below
    assert having(mount, "stem")
    # the info wires cross between the parts: no part covers them, and the stem is broken there
    for r in ("topics", "detects", "reported"):
        assert not any(y0 <= ys[r] <= y1 for _, y0, _, y1 in parts)
        for s in having(mount, "stem"):
            y0, y1 = float(s.get("y")), float(s.get("y")) + float(s.get("height"))
            assert not (y0 < ys[r] < y1)


# ---------------------------------------------------------------- output properties


def test_deterministic(sar):
    states = [{"ram": Fraction(64)}] * (len(SAR_PLAN.steps) + 1)
    a = render_svg(sar, SAR_PLAN, states=states, title="x")
    b = render_svg(_load(EX / "search-and-rescue" / "event1-fresh.cat"), SAR_PLAN, states=states, title="x")
    assert a == b


def test_text_is_escaped(detection):
    plan = Plan([[A("camera-driver", {"out": "a<b&c", "ram-req": Fraction(1)})]])
    svg = render_svg(detection, plan, title="<script>&")
    assert "a&lt;b&amp;c" in svg and "<script>" not in svg
    root = parse(svg)
    assert any("out=a<b&c" in t for t in texts(root))
    assert "<script>&" in texts(root)


def test_control_characters_do_not_break_the_xml(detection):
    plan = Plan([[A("camera-driver", {"out": "bad\x00\x1bvalue", "ram-req": Fraction(1)})]])
    root = parse(render_svg(detection, plan))
    assert any("bad\ufffd\ufffdvalue" in t for t in texts(root))


def test_empty_plan_draws_every_wire(detection):
    root = parse(render_svg(detection, Plan([])))
    assert {g.get("data-resource") for g in having(root, "wire")} == set(detection.resources)
    assert not boxes(root) and not having(root, "port")
    assert not having(root, "step-header")


def test_unknown_morphism_is_drawn_without_ports(detection):
    plan = Plan([[A("no-such-component", {"x": True}), A("mount-rgb-camera")]])
    root = parse(render_svg(detection, plan))
    unknown = [b for b in boxes(root) if "unknown" in classes(b)]
    assert len(unknown) == 1 and not having(unknown[0], "port")
    assert "no-such-component" in texts(root)


# ---------------------------------------------------------------- states


def test_states_annotate_initial_final_and_changes(detection):
    s0 = {"mounted": frozenset(), "ram": Fraction(16), "topics": frozenset(), "detects": frozenset()}
    s1 = {**s0, "mounted": frozenset({"rgb-camera"})}
    s2 = {**s1, "ram": Fraction(15), "topics": frozenset({"image-raw"})}
    s3 = {**s2, "ram": Fraction(11), "detects": frozenset({"person"})}
    root = parse(render_svg(detection, DETECTION_PLAN, states=[s0, s1, s2, s3]))

    initial = {"".join(g.itertext()).strip() for g in having(root, "state", "initial")}
    final = {"".join(g.itertext()).strip() for g in having(root, "state", "final")}
    assert initial == {"∅", "16"}
    assert final == {"{rgb-camera}", "11", "{image-raw}", "{person}"}
    between = {(el.get("data-resource"), "".join(el.itertext())) for el in having(root, "state", "between")}
    # after step 1 only `mounted` changed; after step 2, ram and topics (the last step's values are the final tags)
    assert between == {("mounted", "{rgb-camera}"), ("ram", "15"), ("topics", "{image-raw}")}


def test_states_must_be_one_more_than_steps(detection):
    with pytest.raises(ValueError, match=r"s_0\.\.s_n"):
        render_svg(detection, DETECTION_PLAN, states=[{}])


@pytest.mark.parametrize(
    "value, text",
    [
        (Fraction(16), "16"),
        (Fraction(17, 4), "4.25"),
        (Fraction(-5, 2), "-2.5"),
        (Fraction(1, 20), "0.05"),
        (Fraction(-1, 8), "-0.125"),
        (Fraction(1, 3), "1/3"),
        (Fraction(-7, 6), "-7/6"),
        (3, "3"),
        (True, "true"),
        (False, "false"),
        ("image-raw", "image-raw"),
        (frozenset({"lidar", "battery"}), "{battery, lidar}"),
        (frozenset(), "∅"),
    ],
)
def test_format_value(value, text):
    assert format_value(value) == text


def test_long_theta_labels_wrap(sar):
    root = parse(render_svg(sar, SAR_PLAN))
    det = next(b for b in boxes(root) if b.get("data-morphism") == "open-vocab-detector")
    lines = ["".join(el.itertext()) for el in having(det, "theta")]
    assert len(lines) == 2 and all(len(t) <= max(len("open-vocab-detector"), 26) for t in lines)
    assert " ".join(lines) == "in=rgb-image, target=person, mem=4.5"


def test_odd_morphism_names_stay_well_formed(detection):
    plan = Plan([[A("bad\x00<name>&")]])
    root = parse(render_svg(detection, plan))
    assert [b.get("data-morphism") for b in boxes(root)] == ["bad\ufffd<name>&"]


def test_long_state_values_are_shortened_with_the_full_value_as_tooltip(detection):
    many = frozenset(f"topic-number-{i}" for i in range(6))
    s0 = {"mounted": frozenset(), "ram": Fraction(16), "topics": frozenset(), "detects": frozenset()}
    s1 = {**s0, "topics": many}
    plan = Plan([[A("camera-driver", {"out": "image-raw", "ram-req": Fraction(1)})]])
    root = parse(render_svg(detection, plan, states=[s0, s1]))
    final = next(g for g in having(root, "state", "final") if "topic-number-0" in "".join(g.itertext()))
    shown = "".join(final.find(NS + "text").itertext())
    assert shown.endswith("…") and len(shown) <= 30
    assert final.find(NS + "title").text == format_value(many)
