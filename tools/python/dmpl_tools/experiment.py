"""Experiment configs: resolve, check, write the resolved file.

Resolving (the `experiment.base` chain, --params overlays, --set overrides, the known sections)
is the C++ runtime's (components/runtime/config.cc), run by `dmpl_config`: the rules are written
once, and the tools read exactly what every node reads. What only the tools read is checked
here: `experiment`, `metrics`, `processes`.
"""
import copy
import re
import subprocess

import yaml

from .paths import executable

EXPERIMENT_KEYS = {"name": str, "description": str, "timeout_s": (int, float), "base": str}
METRICS_DEFAULTS = {
    "settle_s": 1.0,            # without a supervisor, the task begins this long after release
    "drop_distance_m": 0.05,    # dropped: the centre moved this far from where it was released...
    "drop_no_contact_s": 0.25,  # ...or no fingertip touched it for this long
    "allow_drop": False,        # the run's status ignores a drop (drop.yaml)
    "contact_loss_s": 0.05,     # a grip contact gone this long counts as lost
    "link_contact_n": 0.05,     # truth force on a finger's links (not its tip): a touch
    "rate_goal_tolerance_rad": 0.05,  # rotation_rate_rad_s: the turn is done this close to it
}


class ExperimentError(Exception):
    pass


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


def resolve(path, params_files=(), sets=(), seed=None):
    """Returns the resolved experiment config (a dict)."""
    args = [executable("dmpl_config"), "--config", str(path)]
    for p in params_files:
        args += ["--params", str(p)]
    for s in sets:
        args += ["--set", s]
    if seed is not None:
        args += ["--set", f"run.seed={int(seed)}"]
    try:
        r = subprocess.run(args, capture_output=True, text=True, errors="replace", timeout=60)
    except FileNotFoundError as e:
        raise ExperimentError(str(e)) from None
    if r.returncode != 0:
        said = (r.stderr.strip().splitlines() or [f"dmpl_config failed ({r.returncode})"])[-1]
        raise ExperimentError(said + _from_set(said, sets))
    config = yaml.safe_load(r.stdout) or {}
    exp = config.setdefault("experiment", {})
    if not isinstance(exp, dict):
        raise ExperimentError(f"{path}: 'experiment' must be a map")
    for key, value in exp.items():
        if key not in EXPERIMENT_KEYS or not isinstance(value, EXPERIMENT_KEYS[key]):
            raise ExperimentError(f"{path}: bad key 'experiment.{key}' (known: "
                                  f"{', '.join(EXPERIMENT_KEYS)})")
    exp.setdefault("name", str(path).rsplit("/", 1)[-1].rsplit(".", 1)[0])
    metrics = config.setdefault("metrics", {})
    if not isinstance(metrics, dict):
        raise ExperimentError(f"{path}: 'metrics' must be a map")
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
