"""Experiment configs: load, overlay --params files, apply --set, check, write the resolved file.

The semantics match the C++ runtime (components/runtime/params.cc): --set key.path=value parses
value as YAML and creates intermediate maps; --params files are merged map by map.
"""
import copy
import re
import subprocess
from pathlib import Path

import yaml

from .paths import executable

# Sections a config may have (components/runtime/config.cc keeps the same list).
KNOWN_SECTIONS = {"run", "hand", "sim", "object", "noise", "ik", "controller", "supervisor",
                  "task", "experiment", "processes", "joint_player", "metrics", "calibration"}

EXPERIMENT_KEYS = {"name": str, "description": str, "timeout_s": (int, float), "base": str}
METRICS_DEFAULTS = {
    "settle_s": 1.0,            # without a supervisor, the task begins this long after release
    "drop_distance_m": 0.05,    # dropped: the centre moved this far from where it was released...
    "drop_no_contact_s": 0.25,  # ...or no fingertip touched it for this long
    "allow_drop": False,        # the run's status ignores a drop (drop.yaml)
    "contact_loss_s": 0.05,     # a grip contact gone this long counts as lost
    "rate_goal_tolerance_rad": 0.05,  # rotation_rate_rad_s: the turn is done this close to it
}


class ExperimentError(Exception):
    pass


def merge(base, overlay):
    """Overlays `overlay` onto `base` in place: maps key by key, anything else replaces."""
    for key, value in overlay.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            merge(base[key], value)
        else:
            base[key] = copy.deepcopy(value)
    return base


def apply_set(config, assignment):
    key, sep, text = assignment.partition("=")
    if not sep or not key:
        raise ExperimentError(f"--set expects key=value, got '{assignment}'")
    try:
        value = yaml.safe_load(text) if text != "" else ""
    except yaml.YAMLError:
        raise ExperimentError(f"--set {key}: cannot parse value '{text}'") from None
    parts = key.split(".")
    if any(not p for p in parts):
        raise ExperimentError(f"--set: empty part in key '{key}'")
    node = config
    for p in parts[:-1]:
        child = node.get(p)
        if child is None:
            child = node[p] = {}
        elif not isinstance(child, dict):
            raise ExperimentError(f"--set {key}: '{p}' is not a map")
        node = child
    node[parts[-1]] = value


def load_yaml(path):
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise ExperimentError(f"cannot open '{path}': {e.strerror}") from None
    except (UnicodeDecodeError, ValueError):
        raise ExperimentError(f"{path}: not a YAML text file (it holds bytes that are not UTF-8 "
                              "text)") from None
    except yaml.YAMLError as e:
        raise ExperimentError(f"{path}: YAML syntax error: {e}") from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ExperimentError(f"{path}: the top level must be a map")
    return data


def load_with_base(path, depth=0):
    """An experiment may build on another: `experiment: {base: other.yaml}` (relative to it)."""
    config = load_yaml(path)
    base = config.get("experiment", {}).get("base") if isinstance(config.get("experiment"), dict) else None
    if not base:
        return config
    if depth > 8:
        raise ExperimentError(f"{path}: experiment.base nests too deep")
    del config["experiment"]["base"]
    return merge(load_with_base(Path(path).parent / base, depth + 1), config)


def resolve(path, params_files=(), sets=(), seed=None):
    """Returns the resolved experiment config (a dict)."""
    config = load_with_base(path)
    for p in params_files:
        merge(config, load_yaml(p))
    for s in sets:
        apply_set(config, s)
    if seed is not None:
        config.setdefault("run", {})["seed"] = int(seed)
    unknown = set(config) - KNOWN_SECTIONS
    if unknown:
        raise ExperimentError(f"{path}: unknown section(s) {', '.join(sorted(unknown))}; known: "
                              f"{', '.join(sorted(KNOWN_SECTIONS))}")
    exp = config.setdefault("experiment", {})
    for key, value in exp.items():
        if key not in EXPERIMENT_KEYS or not isinstance(value, EXPERIMENT_KEYS[key]):
            raise ExperimentError(f"{path}: bad key 'experiment.{key}' (known: "
                                  f"{', '.join(EXPERIMENT_KEYS)})")
    exp.setdefault("name", str(path).rsplit("/", 1)[-1].rsplit(".", 1)[0])
    metrics = config.setdefault("metrics", {})
    for key, value in metrics.items():
        if key not in METRICS_DEFAULTS:
            raise ExperimentError(f"{path}: unknown key 'metrics.{key}' (known: "
                                  f"{', '.join(METRICS_DEFAULTS)})")
        if type(value) is not type(METRICS_DEFAULTS[key]) and not (
                isinstance(value, (int, float)) and isinstance(METRICS_DEFAULTS[key], float)):
            raise ExperimentError(f"{path}: key 'metrics.{key}' has the wrong type: {value!r}")
    for key, value in METRICS_DEFAULTS.items():
        metrics.setdefault(key, value)
    if not config.get("processes"):
        raise ExperimentError(f"{path}: an experiment needs a 'processes' list")
    return config


def check_processes(config_path, config, sets=()):
    """Asks every process of the experiment to validate the resolved config (--check). A
    refusal is one error with what the process wrote (a URDF parser's messages included), and
    names the --set that gave the value when one did."""
    for p in config["processes"]:
        exe = p.get("exec")
        if not exe or not str(exe).startswith("dmpl_"):
            continue
        try:
            r = subprocess.run([executable(exe), "--config", str(config_path), "--check"],
                               capture_output=True, text=True, errors="replace", timeout=60)
        except FileNotFoundError as e:
            raise ExperimentError(str(e)) from None
        if r.returncode != 0:
            lines = [_LOG_PREFIX.sub("", line).rstrip()
                     for line in (r.stderr or r.stdout).strip().splitlines()]
            lines = [line for line in lines if line.strip()][-20:]
            if not lines:
                raise ExperimentError(f"{exe} --check failed ({r.returncode})")
            if len(lines) == 1:
                said = lines[0] if lines[0].startswith(f"{exe}:") else f"{exe}: {lines[0]}"
                raise ExperimentError(said + _from_set(lines[0], sets))
            # What led to the verdict (a parser's messages), then the verdict, as it printed them.
            raise ExperimentError(f"{exe} refused the config:" + "".join(
                f"\n  {line}" for line in lines) + _from_set(lines[-1], sets))


# "[12:20:55.328] [dmpl_sim] [critical] " before each line a node logs.
_LOG_PREFIX = re.compile(r"^\[[0-9:.]+\] \[[^]]*\] \[[a-z]+\] ")


def _from_set(message, sets):
    """' (given with --set KEY=VALUE)' when the key `message` names came from a --set."""
    named = re.findall(r"key '([^']+)'", message)
    for assignment in reversed(sets):  # the last --set of a key is the one that counts
        key = assignment.partition("=")[0]
        if any(n == key or n.startswith(key + ".") for n in named):
            return f" (given with --set {assignment})"
    return ""


def sensing_view(config):
    """The config without the object: what the hand's own software (noise, IK, controller,
    supervisor) is given. Only the simulator knows the object's shape, size, mass and friction."""
    return {k: copy.deepcopy(v) for k, v in config.items() if k != "object"}


def write(config, path):
    with open(path, "w") as f:
        yaml.safe_dump(config, f, sort_keys=False)
