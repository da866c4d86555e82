"""Metrics of a run, from its truth channels (never from the controller's belief).

They read columns (logdata.py): the ones the recorder extracted online from every message of the
run, whatever the log keeps (COLUMNS below are all they need), or those of a recorded log. From an
analysis log (truth at 100 Hz) they approximate these definitions; the run's own summary.json
holds the exact values.

Definitions (the run's config section `metrics` sets the thresholds):
- release: the first SIM_CONTROL RELEASE (t = 0 if the object was never held).
- task begin: the first supervisor status in the task phase; without a supervisor, release +
  metrics.settle_s.
- object_dropped: after release the object's centre moved more than drop_distance_m from where it
  was released, or no fingertip touched it for longer than drop_no_contact_s. Either means the
  hand no longer holds it: it fell out, or lies somewhere the fingertips do not reach.
- max_position_drift_m: largest distance of the centre from its position at task begin.
- rotation_total_rad: rotation about task.axis (palm frame) from task begin to the end, summed
  step by step so that whole turns count.
- final_orientation_error_rad: angle between the final true orientation and the last commanded
  object orientation (the orientation at task begin when nothing was commanded).
- grip_force_total_n: mean over time of the summed fingertip normal forces while held;
  grip_force_peak_n: their largest value (to hold against the object's weight).
- exploration_force_mean_n / _rms_error_n: the truth force of exploring fingers against the
  force asked of them, from 0.25 s after a finger became an explorer (the grip-to-light-touch
  transient is not the exploration).
- grip_force_rms_error_n: RMS of the grip fingers' truth force against the force asked of them.
- contacts_lost: grip fingers (per the supervisor's roles; every finger without a supervisor)
  whose contact disappears for longer than contact_loss_s while the object is held.
- link_contact_s: how long, from task begin, the object touched a finger's link other than its
  tip (truth: the simulator's force on those links above link_contact_n), the posture the
  controller infers from the joints' efforts (LINK_CONTACT events) and the gait avoids.
- rotation_rate_rad_s (gait runs): turning about task.axis, the truth rotation from the first
  rotation step the supervisor commands until the object first comes within
  rate_goal_tolerance_rad of task.angle (the end of the run if it never does), divided by that
  time; toward goal orientations, the angles from where the object was when each reached goal
  became current to that goal, summed, over the time those goals took.
- recoveries: the supervisor's recoveries (a contact lost, a slip, a finger resting on a link,
  a process back), over the whole run.
- palm_turned_rad: the angle between gravity in the palm frame (the simulator's truth) at the
  run's start and at its end: how far the palm turned (sim.palm_motion).
- goals_reached (runs with task.goals or task.random_goals): goals reached one after another;
  time_per_goal_median_s / _p90_s: the time each took, from when it became current.
"""
import numpy as np

from . import channels
from .logdata import angle_between, cumulative_rotation, task_axis
from dmpl import sim_control_t

ROLE_GRIP = 1
ROLE_EXPLORE = 2

# The fields the metrics read, per channel (None: every field); the recorder extracts these.
COLUMNS = {
    channels.SENSORS_TRUE: ["utime", "seq", "object_position", "object_orientation",
                            "tactile_force", "tactile_in_contact", "tactile_link_force",
                            "gravity"],
    channels.CONTROLLER_STATUS: ["utime", "seq", "role", "desired_force"],
    channels.CONTROLLER_REPORT: ["utime", "seq", "role", "desired_force"],
    channels.SUPERVISOR_STATUS: None, channels.TASK: None, channels.SIM_STATUS: None,
    channels.SIM_CONTROL: None,
}


def compute(data, config):
    m = config["metrics"]
    obj = data.object
    summary = {}
    if len(obj) == 0:
        return {"error": "the log has no object truth (DMPL_SENSORS_TRUE)"}
    t = obj.t
    seqs = np.unique(data.truth_seq)
    step = data.truth_tick_step()
    summary["log_missing_ticks"] = int((seqs[-1] - seqs[0]) // step + 1 - len(seqs))
    releases = [seq for seq, cmd, _ in data.controls if cmd == sim_control_t.RELEASE]
    held_at_start = config.get("object", {}).get("held", True)
    t_release = data.time_of_seq(releases[0]) if releases else (None if held_at_start else t[0])
    summary["sim_time_s"] = float(t[-1])
    summary["released_at_s"] = t_release
    _, axis = task_axis(config)

    if t_release is None:
        # Still a verdict: a supervisor that gave up before the release failed the run.
        summary.update(object_dropped=False, note="the object was never released")
        if len(data.supervisor):
            summary.update(_supervisor_verdict(data.supervisor))
        return summary
    i_rel = int(np.searchsorted(t, t_release))
    sup = data.supervisor
    t_begin = None
    if len(sup):
        in_task = [i for i, s in enumerate(sup["grasp_state"]) if s == "Tasks"]
        if in_task:
            t_begin = float(sup.t[in_task[0]])
    if t_begin is None:
        t_begin = t_release + m["settle_s"]
    i_begin = min(int(np.searchsorted(t, t_begin)), len(t) - 1)
    summary["task_began_at_s"] = float(t[i_begin])

    # Drops.
    pos = obj["position"]
    moved = np.linalg.norm(pos[i_rel:] - pos[i_rel], axis=1)
    tact = data.tactile
    dropped = bool(moved.max(initial=0.0) > m["drop_distance_m"])
    if len(tact):
        after = tact.t >= t_release
        touching = tact["in_contact"][after].any(axis=1)
        longest = _longest_false_run(touching, tact.t[after])
        dropped = dropped or longest > m["drop_no_contact_s"]
        summary["longest_no_contact_s"] = float(longest)
    summary["object_dropped"] = dropped

    drift = np.linalg.norm(pos[i_begin:] - pos[i_begin], axis=1)
    summary["max_position_drift_m"] = float(drift.max(initial=0.0))
    duration = t[-1] - t[i_begin]
    summary["drift_rate_m_per_s"] = float(drift[-1] / duration) if duration > 0 else 0.0
    summary["palm_turned_rad"] = _palm_turn(data.gravity)

    q = obj["orientation"]
    rotation = cumulative_rotation(q[i_begin:], axis)
    summary["rotation_total_rad"] = float(rotation[-1]) if len(rotation) else 0.0
    tasks = data.tasks
    targets = tasks["orientation"][tasks["has_target"]] if len(tasks) else []
    target = targets[-1] if len(targets) else q[i_begin]
    summary["final_orientation_error_rad"] = float(angle_between(target[None], q[-1:])[0])

    if len(tact):
        held = (tact.t >= t_release)
        total = tact["force"][held].sum(axis=1)
        summary["grip_force_total_n"] = float(total.mean()) if held.any() else 0.0
        summary["grip_force_peak_n"] = float(total.max(initial=0.0))
        summary["contacts_lost"] = _contacts_lost(data, t_release, m["contact_loss_s"])
        summary["link_contact_s"] = _link_contact_time(tact, t_begin, m["link_contact_n"])
    if len(sup):
        summary["regrasps"] = int(sup["regrasps"][-1])
        summary["recoveries"] = int(sup["recoveries"][-1])
        summary["rotation_commanded_rad"] = float(sup["rotation_commanded"][-1])
        summary["max_tracking_error_rad"] = _tracking_error(data, t, rotation, i_begin)
        summary.update(_supervisor_verdict(sup))
        summary.update(_gait_rate(data, config, t[i_begin:], rotation))
        summary.update(_goals(data, t_begin))
        summary.update(_exploration(data, t_begin))
        summary.update(_grip_force_error(data, t_begin))
    else:
        summary["regrasps"] = 0
        summary["recoveries"] = 0
    if data.sim_status:
        last = data.sim_status
        summary["lockstep_faults"] = int(last["faults"])
        summary["rejected_commands"] = int(last["rejected_commands"])
        if last["last_fault"]:
            summary["last_fault"] = str(last["last_fault"])
    return summary


def _palm_turn(gravity):
    """The angle gravity turned in the palm frame from the first reading to the last (0 in logs
    from before the simulator published it)."""
    if len(gravity) < 2 or not np.all(np.isfinite(gravity[[0, -1]])):
        return 0.0
    a, b = gravity[0], gravity[-1]
    cos = np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.arccos(np.clip(cos, -1.0, 1.0)))


def _first_rotation_time(sup):
    for t, action in zip(sup.t, sup["last_action"]):
        if "rotate" in action:
            return float(t)
    return None


def _gait_rate(data, config, t, rotation):
    """rotation_rate_rad_s about task.axis (see above); nothing for runs that are no gait."""
    sup = data.supervisor
    if not any(a.startswith(("A", "finish")) for a in sup["last_action"]) or len(rotation) == 0:
        return {}
    if sup["has_orientation_goal"].any():
        return {}  # a goal run has its own rate (_goals)
    t0 = _first_rotation_time(sup)
    if t0 is None:
        return {}
    goal = float(config.get("task", {}).get("angle", 0.0))
    tol = config["metrics"]["rate_goal_tolerance_rad"]
    signed = rotation * (1.0 if goal >= 0 else -1.0)
    there = np.nonzero(signed >= abs(goal) - tol)[0]
    i_end = int(there[0]) if len(there) else len(t) - 1
    i0 = min(int(np.searchsorted(t, t0)), i_end)
    duration = t[i_end] - t[i0]
    if duration <= 0:
        return {}
    return {"rotation_rate_rad_s": float((signed[i_end] - signed[i0]) / duration)}


def _goals(data, t_begin):
    """goals_reached, time per goal and the rate toward the goals (see above)."""
    sup = data.supervisor
    has = sup["has_orientation_goal"]
    if not has.any():
        return {}
    reached = sup["goals_reached"]
    out = {"goals_reached": int(reached[-1])}
    # When each goal was reached, and the goal that was current until then.
    steps = np.nonzero(np.diff(reached) > 0)[0] + 1
    times = np.concatenate([[t_begin], sup.t[steps]])
    durations = np.diff(times)
    if len(durations):
        out["time_per_goal_median_s"] = float(np.median(durations))
        out["time_per_goal_p90_s"] = float(np.percentile(durations, 90))
        obj = data.object
        angle = 0.0
        for k, i in enumerate(steps):
            j = min(int(np.searchsorted(obj.t, times[k])), len(obj) - 1)
            goal = sup["orientation_goal"][i - 1]
            angle += float(angle_between(obj["orientation"][j][None], goal[None])[0])
        out["rotation_rate_rad_s"] = angle / float(durations.sum())
    return out


def _supervisor_verdict(sup):
    verdict = {"supervisor_state": sup["grasp_state"][-1],
               "supervisor_finished": bool(sup["finished"][-1]),
               "supervisor_failed": bool(sup["failed"][-1])}
    if verdict["supervisor_failed"]:
        # Why: the supervisor's note when it failed (it keeps it from then on).
        notes = [n for n in sup["note"] if n]
        verdict["supervisor_reason"] = str(notes[-1]) if notes else "no reason given"
    return verdict


def _longest_false_run(flags, times):
    longest, start = 0.0, None
    for flag, t in zip(flags, times):
        if not flag and start is None:
            start = t
        elif flag and start is not None:
            longest, start = max(longest, t - start), None
    if start is not None and len(times):
        longest = max(longest, times[-1] - start)
    return longest


def _roles_at(data, times):
    """Role of each finger at the given times (grip for every finger without a supervisor)."""
    sup = data.supervisor
    nf = len(data.fingers)
    if not len(sup):
        return np.full((len(times), nf), ROLE_GRIP)
    idx = np.clip(np.searchsorted(sup.t, times, side="right") - 1, 0, len(sup) - 1)
    names = data.supervisor_fingers
    order = [names.index(f) if f in names else None for f in data.fingers]
    roles = np.full((len(times), nf), ROLE_GRIP)
    for k, j in enumerate(order):
        if j is not None:
            roles[:, k] = sup["roles"][idx, j]
    return roles


def _link_contact_time(tact, t_begin, threshold_n):
    link = tact["link_force"]
    if np.isnan(link).all():
        return None  # a log from before the simulator published it
    after = tact.t >= t_begin
    touching = (link[after] > threshold_n).any(axis=1)
    if touching.size < 2:
        return 0.0
    dt = np.diff(tact.t[after])
    return float((dt * touching[:-1]).sum())


def _contacts_lost(data, t_release, min_gap):
    """Counts gaps in a grip finger's contact that follow a contact and last over min_gap."""
    tact = data.tactile
    sel = tact.t >= t_release
    times, contact = tact.t[sel], tact["in_contact"][sel]
    roles = _roles_at(data, times)
    lost = 0
    for f in range(contact.shape[1]):
        gap_start, counted, touched = None, False, False
        for i in range(len(times)):
            gripping = roles[i, f] == ROLE_GRIP
            if contact[i, f] or not gripping:
                gap_start = None
                touched = touched or contact[i, f]
                if not gripping:
                    touched = False  # a new grip starts over: it must touch first
                continue
            if not touched:
                continue
            if gap_start is None:
                gap_start, counted = times[i], False
            elif not counted and times[i] - gap_start > min_gap:
                lost += 1
                counted = True
    return lost


def _tracking_error(data, t, rotation, i_begin):
    sup = data.supervisor
    if len(rotation) == 0:
        return 0.0
    tt = t[i_begin:]
    idx = np.clip(np.searchsorted(sup.t, tt, side="right") - 1, 0, len(sup) - 1)
    commanded = sup["rotation_commanded"][idx]
    return float(np.abs(rotation - commanded).max())


def _grip_force_error(data, t_begin):
    """RMS of the grip fingers' truth force against the force the controller asked of them."""
    ctl, tact = data.controller, data.tactile
    if not len(ctl) or not len(tact):
        return {}
    sel = tact.t >= t_begin
    idx = np.clip(np.searchsorted(ctl.t, tact.t[sel], side="right") - 1, 0, len(ctl) - 1)
    mask = ctl["role"][idx] == ROLE_GRIP
    if not mask.any():
        return {}
    err = tact["force"][sel][mask] - ctl["desired_force"][idx][mask]
    return {"grip_force_rms_error_n": float(np.sqrt((err ** 2).mean()))}


def _exploration(data, t_begin, transient_s=0.25):
    """Force of exploring fingers against the force they were asked for (Fig. 9)."""
    ctl, tact = data.controller, data.tactile
    if not len(ctl) or not len(tact):
        return {}
    sel = tact.t >= t_begin
    times = tact.t[sel]
    idx = np.clip(np.searchsorted(ctl.t, times, side="right") - 1, 0, len(ctl) - 1)
    roles, desired = ctl["role"][idx], ctl["desired_force"][idx]
    force = tact["force"][sel]
    exploring = roles == ROLE_EXPLORE
    mask = np.zeros_like(exploring)
    for f in range(exploring.shape[1]):
        since = None
        for i, t in enumerate(times):
            if not exploring[i, f]:
                since = None
                continue
            since = t if since is None else since
            mask[i, f] = t - since >= transient_s
    if not mask.any():
        return {}
    err = force[mask] - desired[mask]
    dt = float(np.median(np.diff(times))) if len(times) > 1 else 0.0
    return {"exploration_force_mean_n": float(force[mask].mean()),
            "exploration_force_rms_error_n": float(np.sqrt((err ** 2).mean())),
            "exploration_time_s": float(exploring.any(axis=1).sum() * dt)}
