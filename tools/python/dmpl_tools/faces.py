"""The face each finger touches over time, as the hand felt it against the truth (issue 29).

For an object whose faces the run's config gives (a box: its six; a prism: its sides and its two
ends), each contact's outward normal in the object frame is labelled with the face whose normal
is nearest: detected, from the controller's status (the normal from the fingertip's centre
through its sensed contact point, into the object frame by the controller's pose estimate: what
the supervisor's surface model and edge detector see), and true, from the simulator's contact
normal and the object's true orientation. Other shapes have no faces to name."""
import numpy as np

from . import channels
from .logdata import _t, quat_conj, quat_mul

TRUTH_FIELDS = ["object_orientation", "tactile_normal", "tactile_in_contact"]
CONTROLLER_FIELDS = ["object_orientation", "tip_position", "contact_position", "in_contact",
                     "force"]
# What the supervisor takes for a contact (Blackboard::LearnSurface): a reading of at least this
# force, its point on the tip's sphere.
MIN_FORCE_N = 0.05
TIP_RADIUS_RANGE_M = (0.002, 0.03)


def face_normals(obj):
    """The object's face names and outward unit normals (object frame), or None."""
    shape = obj.get("shape", "sphere")
    if shape == "box":
        names = ["+x", "-x", "+y", "-y", "+z", "-z"]
        return names, np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1],
                                [0, 0, -1]], dtype=float)
    if shape == "prism":
        n = int(obj.get("sides", 6))
        # Corners at 2 pi k / n (the simulator's): side k faces halfway between two corners.
        a = (2 * np.arange(n) + 1) * np.pi / n
        sides = np.c_[np.cos(a), np.sin(a), np.zeros(n)]
        return ([f"side {k}" for k in range(n)] + ["+z end", "-z end"],
                np.vstack([sides, [[0, 0, 1], [0, 0, -1]]]))
    return None


def _rotate_into(q, v):
    """v (palm frame, [ticks, fingers, 3]) into the frame of orientation q ([ticks, 4], w x y z):
    q* v q per finger."""
    q = q[..., None, :]
    pure = np.concatenate([np.zeros(v.shape[:-1] + (1,)), v], axis=-1)
    return quat_mul(quat_conj(q), quat_mul(pure, q))[..., 1:]


def faces_over_time(data, obj):
    """(names, t_true, true_labels, t_detected, detected_labels) with labels [ticks, fingers]
    (-1: no contact), or None when the shape has no faces or the log lacks the columns."""
    faces = face_normals(obj)
    truth = data.columns.table(channels.SENSORS_TRUE)
    status, report = channels.CONTROLLER_STATUS, channels.CONTROLLER_REPORT
    use = status if data.columns.rows(status) >= 5 * data.columns.rows(report) else report
    ctl = data.columns.table(use)
    if faces is None or any(k not in truth for k in TRUTH_FIELDS) or \
            any(k not in ctl for k in CONTROLLER_FIELDS):
        return None
    names, normals = faces

    def label(outward, touching):
        lab = np.argmax(outward @ normals.T, axis=-1)
        return np.where(touching, lab, -1)

    true_out = _rotate_into(truth["object_orientation"], truth["tactile_normal"])
    true_labels = label(true_out, truth["tactile_in_contact"].astype(bool))
    out = ctl["tip_position"] - ctl["contact_position"]
    length = np.linalg.norm(out, axis=-1, keepdims=True)
    out = np.divide(out, length, out=np.zeros_like(out), where=length > 1e-9)
    felt = (ctl["in_contact"].astype(bool) & (ctl["force"] >= MIN_FORCE_N) &
            (length[..., 0] > TIP_RADIUS_RANGE_M[0]) & (length[..., 0] < TIP_RADIUS_RANGE_M[1]))
    detected = label(_rotate_into(ctl["object_orientation"], out), felt)
    return names, _t(truth), true_labels, _t(ctl), detected


def agreement(result):
    """The share of the time both say a finger touches in which they name the same face."""
    names, t_true, true_labels, t_det, det = result
    idx = np.clip(np.searchsorted(t_true, t_det), 0, len(t_true) - 1)
    truth_at = true_labels[idx]
    both = (truth_at >= 0) & (det >= 0)
    return float((truth_at[both] == det[both]).mean()) if both.any() else float("nan")


def plot(result, fingers, path, plt):
    names, t_true, true_labels, t_det, det = result
    fig, axes = plt.subplots(len(fingers), 1, figsize=(8, 1.4 * len(fingers) + 1), sharex=True,
                             sharey=True)
    for f, name in enumerate(fingers):
        ax = axes[f]
        ax.plot(t_true, np.where(true_labels[:, f] >= 0, true_labels[:, f], np.nan), lw=2.5,
                color="#90caf9", label="true" if f == 0 else None)
        ax.plot(t_det, np.where(det[:, f] >= 0, det[:, f], np.nan), lw=0.9, color="#d62728",
                label="detected (by touch)" if f == 0 else None)
        ax.set_ylabel(name)
        ax.set_yticks(range(len(names)))
        ax.set_yticklabels(names, fontsize=7)
        ax.grid(alpha=0.3)
    axes[0].set_title("The face each finger touches: detected by touch against true")
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
