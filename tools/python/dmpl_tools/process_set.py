"""A process set: the YAML a launcher starts (schema, validation, ${variables}).

A set file:

    name: noise_demo
    lcm_url: udpm://239.255.76.67:7667?ttl=0   # optional; else $LCM_DEFAULT_URL, else the default
    record: true                                # dmpl_record -> RUN_DIR/run.lcmlog
    record_policy: full                         # full | analysis | none (record_policy.h)
    processes:
      - name: noise
        exec: dmpl_noise                        # build/bin first, then PATH
        args: [--config, "${root}/configs/experiments/static_grasp.yaml"]
        env: {DMPL_LOG_LEVEL: info}
        group: sensing
        start_order: 0                          # lower starts first; ties keep file order
        wait_for_heartbeat: true                # the next process starts once this one beats
        auto_respawn: true
        respawn_delay_s: 0.5                    # doubles per restart, up to 8 s
        max_restarts: 3
        stop_signal: SIGINT
        stop_time_allowed: 5.0                  # then SIGKILL
        exit_ends_set: false                    # when this process exits, stop the set
        cpus: [-1]                              # CPU affinity (negative: from the last CPU)

A set-level `cpus` applies to every process that names none; the recorder then runs on the
other CPUs (affinity.py says why pinning pays).

The keys a file may hold and their types are the fields of ProcessSpec and ProcessSet: the
schema is written once, here.
"""
import dataclasses
import os
import re
import signal
from dataclasses import dataclass, field

import yaml

from .affinity import resolve_cpus
from .paths import executable

RECORD_POLICIES = ("full", "analysis", "none")  # components/logging/record_policy.h


class SetError(Exception):
    """A bad process set file: reported before anything starts."""


@dataclass
class ProcessSpec:
    name: str
    exec: str
    args: list = field(default_factory=list)
    env: dict = field(default_factory=dict)
    group: str = ""
    start_order: int = 0
    wait_for_heartbeat: bool = False
    heartbeat_timeout_s: float = 10.0
    auto_respawn: bool = False
    respawn_delay_s: float = 0.5
    max_restarts: int = 3
    stop_signal: str = "SIGINT"
    stop_time_allowed: float = 5.0
    exit_ends_set: bool = False
    required: bool = True
    cpus: list = field(default_factory=list)  # resolved CPU ids; empty: no affinity


@dataclass
class ProcessSet:
    name: str
    processes: list  # of ProcessSpec
    lcm_url: str = ""
    record: bool = True
    record_channels: str = ".*"
    record_policy: str = "full"
    heartbeat_timeout_s: float = 10.0
    status_period_s: float = 0.5
    cpus: list = field(default_factory=list)


def _schema(cls):
    """{key: accepted types} from a dataclass's fields; a float field also takes an int."""
    return {f.name: (int, float) if f.type is float else f.type for f in dataclasses.fields(cls)}


def _check_keys(where, data, schema):
    if not isinstance(data, dict):
        raise SetError(f"{where}: expected a map, got {type(data).__name__}")
    for key, value in data.items():
        if key not in schema:
            raise SetError(f"{where}: unknown key '{key}'; known keys: {', '.join(sorted(schema))}")
        want = schema[key]
        if isinstance(value, bool) and want in ((int, float), int):
            raise SetError(f"{where}: key '{key}' expects a number, got {value!r}")
        if not isinstance(value, want):
            names = want.__name__ if isinstance(want, type) else " or ".join(t.__name__ for t in want)
            raise SetError(f"{where}: key '{key}' expects {names}, got {value!r}")


def substitute(text, variables):
    """Replaces ${var} with variables[var] or the environment; an unknown variable is an error."""
    def repl(match):
        key = match.group(1)
        if key in variables:
            return str(variables[key])
        if key in os.environ:
            return os.environ[key]
        raise SetError(f"unknown variable ${{{key}}} in '{text}'")
    return re.sub(r"\$\{(\w+)\}", repl, str(text))


def _cpus(cpus, where):
    try:
        return resolve_cpus(cpus)
    except ValueError as e:
        raise SetError(f"{where}: key 'cpus': {e}") from None


def _parse_process(p, where, set_cpus, variables):
    _check_keys(where, p, _schema(ProcessSpec))
    for required in ("name", "exec"):
        if required not in p:
            raise SetError(f"{where}: missing key '{required}'")
    spec = ProcessSpec(**p)
    spec.cpus = _cpus(spec.cpus or set_cpus, where)
    spec.args = [substitute(a, variables) for a in spec.args]
    spec.env = {str(k): substitute(v, variables) for k, v in spec.env.items()}
    try:
        spec.exec = executable(substitute(spec.exec, variables))
    except FileNotFoundError as e:
        raise SetError(f"{where}: {e}") from None
    if not spec.stop_signal.startswith("SIG") or not hasattr(signal, spec.stop_signal):
        raise SetError(f"{where}: unknown stop_signal '{spec.stop_signal}'")
    if spec.stop_time_allowed <= 0 or spec.respawn_delay_s < 0 or spec.max_restarts < 0:
        raise SetError(f"{where}: stop_time_allowed must be > 0, respawn_delay_s and "
                       "max_restarts >= 0")
    return spec


def parse_set(data, source, variables):
    """Validates a process set (a dict from YAML) and returns a ProcessSet. Raises SetError."""
    _check_keys(source, data, _schema(ProcessSet))
    if "name" not in data:
        raise SetError(f"{source}: missing key 'name'")
    if not data.get("processes"):
        raise SetError(f"{source}: 'processes' must list at least one process")
    procs = []
    for i, p in enumerate(data["processes"]):
        where = f"{source}: processes[{i}]"
        procs.append(_parse_process(p, where, data.get("cpus", []), variables))
        if procs[-1].name in (q.name for q in procs[:-1]):
            raise SetError(f"{where}: duplicate process name '{procs[-1].name}'")
    fields = {k: v for k, v in data.items() if k != "processes"}
    if "cpus" in fields:
        fields["cpus"] = _cpus(fields["cpus"], source)
    if "lcm_url" in fields:
        fields["lcm_url"] = substitute(fields["lcm_url"], variables)
    pset = ProcessSet(processes=procs, **fields)
    try:
        re.compile(pset.record_channels)
    except re.error as e:
        raise SetError(f"{source}: record_channels is not a valid regex: {e}") from None
    if pset.record_policy not in RECORD_POLICIES:
        raise SetError(f"{source}: record_policy '{pset.record_policy}': expected one of "
                       f"{', '.join(RECORD_POLICIES)}")
    return pset


def _read_yaml(path):
    try:
        with open(path) as f:
            return yaml.safe_load(f)
    except OSError as e:
        raise SetError(f"cannot open process set '{path}': {e.strerror}") from None
    except yaml.YAMLError as e:
        raise SetError(f"{path}: YAML syntax error: {e}") from None
    except UnicodeDecodeError:
        raise SetError(f"{path}: not a text file (a process set is YAML)") from None


def load_set(path, variables):
    return parse_set(_read_yaml(path) or {}, str(path), variables)


def peek_name(path):
    """The set's name, before it is parsed (the run directory is named after it)."""
    data = _read_yaml(path) or {}
    return str(data.get("name", "set")) if isinstance(data, dict) else "set"
