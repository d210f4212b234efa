"""Scoring the keypoint contact network on filmed dataset splits: contact precision, recall and
F1 (contactvision §6.2) and gait-parameter errors against the physics labels (§6.5.2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from perception.contact_transformer import ContactTransformer, detect_contacts
from perception.contacts import detection_scores, tolerance_curve
from perception.gait import gait_cycles, gait_parameters, gait_phases
from perception.keypoint_data import KeypointSequence, View, ViewConfig, film

GAIT_RATIOS = ("stance", "swing", "single_support", "double_support")


@dataclass
class FilmedSequence:
    """One sequence seen from one view: ``keypoints (T, K, 3)`` (pixels, confidence), Γ
    ``labels (T, 4)``, ``fps``, source ``clip`` and ``view`` name."""

    keypoints: np.ndarray
    labels: np.ndarray
    fps: float
    clip: str
    view: str


def film_split(sequences: list[KeypointSequence], views: list[View], keypoints: str = "lower", seed: int = 0,
               test: bool = False, config: ViewConfig = ViewConfig()) -> list[FilmedSequence]:
    """Every sequence filmed from every view (noise seeded by ``seed``, sequence and view)."""
    out = []
    for i, s in enumerate(sequences):
        for j, view in enumerate(views):
            rng = np.random.default_rng([seed, i, j])
            out.append(FilmedSequence(film(s.points, view, rng, s.fps, keypoints, test, config), s.labels, s.fps,
                                      s.clip, view.name))
    return out


def predict_contacts(net: ContactTransformer, filmed: list[FilmedSequence], progress: bool = False) -> list[np.ndarray]:
    """Contacts ``(T, 4)`` bool (:func:`~perception.contact_transformer.detect_contacts`) of each
    filmed sequence."""
    return [detect_contacts(net, f.keypoints, f.fps)
            for f in tqdm(filmed, desc="contacts", unit="sequence", disable=not progress)]


def gait_errors(predicted: list[np.ndarray], truth: list[np.ndarray]) -> dict:
    """Mean absolute errors (percentage points) of each gait ratio between predicted and true
    contacts: ``sequence`` compares the ratios over whole sequences whose truth shows a gait;
    ``cycle`` compares them over each complete true gait cycle (heel strike to heel strike of the
    right foot, as ContactVision measures one cycle per video), the predicted ratios taken over
    the same frames. ``count`` spans are compared, out of ``truth_count`` where the truth shows a
    gait (the rest had no valid predicted frame)."""
    errors: dict[str, dict[str, list[float]]] = {"sequence": {k: [] for k in GAIT_RATIOS},
                                                 "cycle": {k: [] for k in GAIT_RATIOS}}
    totals = {"sequence": 0, "cycle": 0}
    for p, t in zip(predicted, truth):
        pp, tp = gait_phases(p), gait_phases(t)
        spans = {"sequence": [(0, len(t))], "cycle": gait_cycles(tp)}
        for scope, ranges in spans.items():
            for a, b in ranges:
                gp, gt = gait_parameters(pp[a:b]).as_dict(), gait_parameters(tp[a:b]).as_dict()
                if gt["valid_frames"] == 0:
                    continue
                totals[scope] += 1
                if gp["valid_frames"] == 0:
                    continue
                for k in GAIT_RATIOS:
                    errors[scope][k].append(100.0 * abs(gp[k] - gt[k]))
    return {scope: {**{f"{k}_mae_pp": float(np.mean(v)) if v else float("nan") for k, v in e.items()},
                    "count": len(e["stance"]), "truth_count": totals[scope]} for scope, e in errors.items()}


def evaluate_keypoint_contacts(net: ContactTransformer, filmed: list[FilmedSequence], progress: bool = False) -> dict:
    """Scores over ``filmed``: ``{channel: {precision, recall, f1}}`` pooled over every frame and
    view, ``overall`` F1 per view, overall F1 against temporal tolerance
    (:func:`~perception.contacts.tolerance_curve`), and gait-ratio MAE (:func:`gait_errors`)."""
    if not filmed:
        raise ValueError("no filmed sequences to evaluate")
    predicted = predict_contacts(net, filmed, progress)
    truth = [f.labels for f in filmed]
    out = {"frames": int(sum(len(t) for t in truth)), "sequences": len(filmed),
           "scores": detection_scores(np.concatenate(predicted), np.concatenate(truth))}
    by_view: dict[str, list[int]] = {}
    for k, f in enumerate(filmed):
        by_view.setdefault(f.view, []).append(k)
    out["f1_by_view"] = {v: detection_scores(np.concatenate([predicted[k] for k in ks]),
                                             np.concatenate([truth[k] for k in ks]))["overall"]["f1"]
                         for v, ks in by_view.items()}
    out["f1_by_tolerance_s"] = tolerance_curve(predicted, truth, [f.fps for f in filmed])
    out["gait"] = gait_errors(predicted, truth)
    return out
