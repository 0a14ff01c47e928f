"""hbfriction: frequency responses of structures with friction contacts by multi-harmonic balance.

The Python face of the C++ library (``include/hbf/*.hpp``): the same computations as the ``hbf``
command, with NumPy arrays in and out.

    >>> import hbfriction
    >>> b = hbfriction.frf(hbfriction.absorber())        # the paper's absorber, exact Coulomb
    >>> b.w, b.y1_max                                      # NumPy columns, as hbf frf's CSV
    >>> b.metadata["peaks"], b.status                     # hbf frf --summary's JSON, as a dict

Systems: ``absorber(law, r=..., mu=...)`` (the paper's preset), ``load("system.toml")`` (the
TOML files of hbf frf --config), or ``System(mass, stiffness, excitation, damping, contacts)``
from NumPy arrays or SciPy sparse matrices (``Contact(dof=0, other_dof=1, law="jenkins",
friction_limit=0.2, stiffness=1.6)``; DOFs are 0-based).

Computations: ``frf``, ``solve_at``, ``timeint``, ``analytic``, ``optimize``, ``map``. Their
options carry the C++ names and defaults (``harmonics``, ``omega_start``, ``tolerance``,
``max_amplitude``, ...; see ``options()``). Bad input raises ValueError with the library's
message (naming the parameter and its allowed range); a wrong type raises TypeError. A result
that is incomplete or doubtful is never silent: its ``status`` says so and an
``IncompleteResultWarning`` is issued. The GIL is released while the C++ code computes.
"""

import json as _json
import math as _math
import sys as _sys
import warnings as _warnings

from . import _build, _core


def _import_numpy():
    """NumPy: this interpreter's, else (an interpreter of the version the extension was built
    for, without NumPy of its own, e.g. a pyenv Python beside Debian's) the NumPy of the
    interpreter it was built with, imported from there alone."""
    try:
        import numpy
        return numpy
    except ImportError:
        pass
    if _build.NUMPY_SITE and _sys.version_info[:2] == _build.PYTHON_VERSION:
        _sys.path.append(_build.NUMPY_SITE)
        try:
            import numpy
            return numpy
        except ImportError:
            pass
        finally:
            _sys.path.remove(_build.NUMPY_SITE)
    raise ImportError("hbfriction needs NumPy, which %s does not have: use %s (the interpreter hbfriction was "
                      "built for), or install NumPy for this one" % (_sys.executable, _build.PYTHON_EXECUTABLE))


_np = _import_numpy()
from ._core import (AbsorberParameters, Contact, ContinuationOptions, CorrectorOptions, FrfSettings,
                    HarmonicBalanceOptions, OptimizeOptions, Output, StabilityOptions, System,
                    TimeIntegrationOptions)

__version__ = _core.__version__
# hbfriction.map is left out of __all__: a star import would hide the built-in map.
__all__ = ["absorber", "load", "reduce", "check_output", "System", "Contact", "Output", "frf", "solve_at", "timeint", "exact_branch", "modes", "analytic",
           "nodal_diameters",
           "optimize", "track", "TrackResult", "TrackCurve", "options", "Branch", "Solution", "Table", "ModeResult", "OptimizeResult", "MapResult",
           "IncompleteResultWarning", "SolveError", "AbsorberParameters", "FrfSettings",
           "HarmonicBalanceOptions", "ContinuationOptions", "CorrectorOptions", "StabilityOptions",
           "TimeIntegrationOptions", "OptimizeOptions"]


class IncompleteResultWarning(UserWarning):
    """A result that is incomplete or doubtful (its status and messages say why)."""


class SolveError(RuntimeError):
    """No solution where one was asked for (solve_at: the branch stopped before the frequency;
    modes: the backbone's first point did not converge)."""


# ---- option classes: keyword construction and a readable repr ---------------------------------

def _fields(obj):
    return [n for n in dir(type(obj)) if not n.startswith("_") and not callable(getattr(type(obj), n, None))
            and n not in ("ground",)]


def _assign(target, name, value, where=None):
    """setattr(target, name, value) for a field of a C++ options struct, with the type checked
    against the field's current value: an int field takes an integer (not a bool) within C's
    int, a float field a real number (not a bool), a bool field a bool, a list of numbers a
    sequence of real numbers (not a string). TypeError or ValueError names the argument."""
    label = where or name
    current = getattr(target, name)
    if isinstance(current, bool):
        if not isinstance(value, (bool, _np.bool_)):
            raise TypeError("%s = %r: expected True or False" % (label, value))
        value = bool(value)
    elif isinstance(current, int):
        if isinstance(value, (bool, _np.bool_)) or not isinstance(value, (int, _np.integer)):
            raise TypeError("%s = %r: expected an integer (%s)" % (label, value, type(value).__name__))
        if not -2 ** 31 <= int(value) < 2 ** 31:
            raise ValueError("%s = %d is out of range of integers" % (label, value))
        value = int(value)
    elif isinstance(current, float):
        if isinstance(value, (bool, _np.bool_)) or not isinstance(value, (int, float, _np.integer, _np.floating)):
            raise TypeError("%s = %r: expected a number (%s)" % (label, value, type(value).__name__))
        value = float(value)
    elif isinstance(current, str):
        if not isinstance(value, str):
            raise TypeError("%s = %r: expected a string" % (label, value))
    elif isinstance(current, list) and name == "at":
        if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
            raise TypeError("%s = %r: expected a sequence of frequencies (numbers)" % (label, value))
        items = list(_np.asarray(value, dtype=object).ravel()) if isinstance(value, _np.ndarray) else list(value)
        for v in items:
            if isinstance(v, (bool, _np.bool_)) or not isinstance(v, (int, float, _np.integer, _np.floating)):
                raise TypeError("%s: %r is not a number" % (label, v))
        value = [float(v) for v in items]
    try:
        setattr(target, name, value)
    except TypeError:
        raise TypeError("%s = %r: not allowed for this option (%s)" % (label, value, type(current).__name__)) from None


def _integer(label, value):
    """value as an int: a Python or NumPy integer (not a bool, a float or a string)."""
    if isinstance(value, (bool, _np.bool_)) or not isinstance(value, (int, _np.integer)):
        raise TypeError("%s = %r: expected an integer (%s)" % (label, value, type(value).__name__))
    if not -2 ** 31 <= int(value) < 2 ** 31:
        raise ValueError("%s = %d is out of range of integers" % (label, value))
    return int(value)


def _real(label, value):
    """value as a float: a Python or NumPy real number (not a bool or a string)."""
    if isinstance(value, (bool, _np.bool_)) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise TypeError("%s = %r: expected a number (%s)" % (label, value, type(value).__name__))
    return float(value)


def _positive(label, value):
    """value as a float > 0 (finite)."""
    v = _real(label, value)
    if not (v > 0.0 and _math.isfinite(v)):
        raise ValueError("%s = %r is out of range: allowed > 0" % (label, value))
    return v


def _reals(label, values):
    """A number or a sequence of numbers as a list of floats (a string or a bool is refused)."""
    if isinstance(values, (str, bytes)):
        raise TypeError("%s = %r: expected a number or a sequence of numbers (%s)" % (label, values, type(values).__name__))
    items = list(values) if _np.ndim(values) > 0 else [values]
    return [_real("%s[%d]" % (label, k) if len(items) > 1 else label, v) for k, v in enumerate(items)]


def _keyword_init(cls):
    core_init = cls.__init__

    def __init__(self, *args, **values):
        core_init(self, *args)
        for name, value in values.items():
            if name.startswith("_") or name not in _fields(self):
                raise ValueError("%s: unknown option '%s': allowed %s" % (cls.__name__, name, ", ".join(_fields(self))))
            _assign(self, name, value)

    def __repr__(self):
        return "%s(%s)" % (cls.__name__, ", ".join("%s=%r" % (n, getattr(self, n)) for n in _fields(self)))

    __init__.__doc__ = "``%s(**fields)``: the C++ struct's fields by name, the C++ defaults otherwise" % cls.__name__
    cls.__init__ = __init__
    cls.__repr__ = __repr__


for _cls in (AbsorberParameters, Contact, ContinuationOptions, CorrectorOptions, FrfSettings, HarmonicBalanceOptions,
             OptimizeOptions, StabilityOptions, TimeIntegrationOptions):
    _keyword_init(_cls)


def _copy(obj, kind=None):
    """A copy of an options object (through its fields); TypeError unless it is a `kind`."""
    if kind is not None and not isinstance(obj, kind):
        raise TypeError("%r is not an hbfriction.%s" % (obj, kind.__name__))
    new = type(obj)()
    for n in _fields(obj):
        value = getattr(obj, n)
        if type(value) in (ContinuationOptions, CorrectorOptions, HarmonicBalanceOptions, StabilityOptions):
            value = _copy(value)
        setattr(new, n, value)
    return new


# ---- systems ------------------------------------------------------------------------------------

# The paper's symbols (hbf's flags) for the fields of AbsorberParameters, and the laws each applies
# to: r, wa, mu, fe for every law, the others from the registry of contact laws (contact_law.hpp,
# model.hpp: preset_parameters).
_ABSORBER_NAMES = {"r": "mass_ratio", "wa": "tuning_ratio", "mu": "friction_coefficient", "fe": "excitation"}
_ABSORBER_NAMES.update({p["keyword"]: p["field"] for p in _core.preset_parameters()})
_KEYWORDS = {p["field"]: p["keyword"] for p in _core.preset_parameters()}
_LAWS = tuple(law["name"] for law in _core.contact_laws() if law["preset"])  # the absorber's


def absorber(law="coulomb", parameters=None, excitation_harmonic=1, **values):
    """The paper's friction absorber (2 DOFs, nondimensional; model.hpp) as a System.

    law: coulomb (exact, set-valued), jenkins, dahl, lugre or coulomb-reg. Parameters by the
    paper's symbols or the C++ names of AbsorberParameters (defaults: r = 0.1, wa = 1, mu = 0.2,
    fe = 0.5, wb = 0.4, xi = 0.01, eps = 0.05): r/mass_ratio, wa/tuning_ratio,
    mu/friction_coefficient, fe/excitation, wb/contact_stiffness_ratio (dahl, lugre, jenkins),
    xi/contact_damping_ratio (lugre), eps/regularization (coulomb-reg), mu_static, stribeck_velocity,
    viscous (lugre), dlft_eps/lagrangian_penalty (coulomb). A parameter that does not apply to the
    law is an error, as in hbf. Reports y1 and y2.
    """
    if law not in _LAWS:
        if law in (l["name"] for l in _core.contact_laws()):
            raise ValueError("law = '%s' has no preset: the paper's absorber has no normal direction (allowed %s; "
                             "build a System with the contact's normal_direction)" % (law, ", ".join(_LAWS)))
        raise ValueError("law = '%s' is not known: allowed %s" % (law, ", ".join(_LAWS)))
    p = AbsorberParameters() if parameters is None else _copy(parameters, AbsorberParameters)
    fields = set(_fields(p))
    given = []  # the law's parameters given, by their keywords
    for key, value in values.items():
        name = _ABSORBER_NAMES.get(key, key)
        if name not in fields:
            raise ValueError("absorber: unknown parameter '%s': allowed %s (or the C++ names %s)" %
                             (key, ", ".join(_ABSORBER_NAMES), ", ".join(sorted(fields))))
        _assign(p, name, value, key)
        if name in _KEYWORDS:
            given.append(_KEYWORDS[name])
    _core.check_given_preset_parameters(law, p, given)  # as hbf: a parameter the law does not read, an explicit 0
    p.validate(law)
    system = _core.friction_absorber(p, law)
    if isinstance(excitation_harmonic, bool) or excitation_harmonic != 1:
        system.excitation_harmonic = excitation_harmonic
        system.validate()
    return system


def load(path):
    """A System from a TOML file (the system-file reference; examples/systems/): its structure,
    contacts and outputs, and its [frequency] and [solver] settings, which frf() applies unless
    given as options (as hbf frf --config)."""
    try:
        return _core.read_system_config(str(path))
    except ValueError as e:  # the library names the file as hbf's flag does
        raise ValueError(str(e).replace("--config = ", "path = ", 1)) from None


def _add_interface(self, nodes, normal, *, tangent=None, area=None, preload_pressure=0.0, name="", contact=None,
                   **parameters):
    """Adds a meshed contact interface (include/hbf/interface.hpp; a file's [[interface]]): one
    contact per node against a rigid counter-face, in node order, and the preload pressure's
    static load. Returns the interface as in ``interfaces`` (name, first, count, dimension).

    nodes: an n x 2 (2D) or n x 3 (3D) array of each node's DOFs (0-based; x, y(, z)).
    normal: the closing direction, one for every node (d numbers) or one per node (n x d), unit.
    tangent (3D): t1, orthogonal to the normal (one or n x 3; default: the axis least aligned
    with the normal, made orthogonal); t2 = n x t1. In 2D t1 is the normal turned by -90 degrees.
    area: the nodes' areas (one number or n; default 1): the law's per-area parameters (law
    elastic: stiffness k_t, normal_stiffness k_n, preload N_0) are per unit area.
    preload_pressure: p >= 0, the static load p A_k n on node k.
    contact: a Contact prototype (its law and parameters; dof and directions are set per node), or
    the law and its parameters as keywords: law="elastic" (the default), friction_coefficient=...,
    stiffness=..., normal_stiffness=....
    Add interfaces to the FE system, then reduce() it: the nodes' DOFs are kept.
    """
    if contact is None:
        contact = Contact(law=parameters.pop("law", "elastic"), **parameters)
    elif parameters:
        raise TypeError("add_interface: give the law's parameters in contact= or as keywords, not both (got %s)"
                        % ", ".join(sorted(parameters)))
    area = None if area is None else _np.atleast_1d(_np.asarray(area, dtype=float))
    return self._add_interface(nodes, normal, contact, tangent, area, float(preload_pressure), str(name))


System.add_interface = _add_interface


def reduce(system, modes, *, method="craig-bampton", interface=None, damping_ratios=None, rayleigh=None):
    """The FE system reduced onto its contacts' DOFs (include/hbf/reduction.hpp; a file's
    [reduction]): a new System on the retained DOFs (first, in order) and `modes` normal modes,
    with its contacts, loads, outputs and interfaces carried over, and ``recovery`` (T: y = T q),
    ``retained``, ``mode_frequencies`` and ``fe_outputs(dofs)`` for results on any FE DOF.

    method: "craig-bampton" (fixed-interface modes), "massless-boundary" (CBMB: massless
    retained coordinates) or "macneal" (free-interface modes with residual flexibility).
    interface: the FE DOFs to keep (0-based; default: every DOF a contact acts on, ascending);
    the DOFs the excitation and static load act on are kept too.
    damping_ratios: modal ratios of the reduced model's modes (the last one repeated), or
    rayleigh=(a, b): C_r = a M_r + b K_r; neither: the FE damping projected (T^T C T).
    ``dropped_mass_fraction`` (massless-boundary): the mass dropped, as a fraction of trace(M);
    above 1 % an IncompleteResultWarning says how much and where (``reduction_warnings``).
    """
    if not isinstance(system, System):
        raise TypeError("reduce: system must be an hbfriction.System, got %s" % type(system).__name__)
    if not isinstance(method, str):
        raise TypeError("method = %r: expected a string (craig-bampton, massless-boundary or macneal)" % (method,))
    reduced = _core.reduce_system(system, _integer("modes", modes), method, interface, damping_ratios, rayleigh)
    for w in reduced.reduction_warnings:
        _warnings.warn(w, IncompleteResultWarning, stacklevel=2)
    return reduced


def _outputs(system, outputs):
    """Output objects from DOF indices (0-based), Output objects, or (name, row) pairs where row
    holds c (N numbers: o = c^T y)."""
    result = []
    for o in ([outputs] if isinstance(outputs, (int, Output, tuple)) else outputs):
        if isinstance(o, Output):
            result.append(o)
        elif isinstance(o, (int, _np.integer)) and not isinstance(o, bool):
            if not 0 <= int(o) < system.dofs:
                raise ValueError("outputs: DOF %d is out of range: allowed 0..%d" % (o, system.dofs - 1))
            result.append(Output.dof(int(o)))
        elif isinstance(o, tuple) and len(o) == 2:
            row = _np.asarray(o[1], dtype=float).ravel()
            if row.size != system.dofs:
                raise ValueError("outputs: '%s' has %d coefficients: allowed %d (one per DOF)" % (o[0], row.size,
                                                                                                 system.dofs))
            result.append(Output(str(o[0]), [(int(i), float(row[i])) for i in _np.flatnonzero(row)]))
        else:
            raise TypeError("outputs: %r is not a DOF index, an Output or a (name, row) pair" % (o,))
    if not result:
        raise ValueError("outputs: empty: allowed one or more DOFs or outputs")
    for o in result:
        if not o.terms:
            raise ValueError("outputs: '%s' has no non-zero coefficient" % o.name)
    return result


def _check_system(system):
    if not isinstance(system, System):
        raise TypeError("system: %r is not an hbfriction.System (absorber(), load() or System(...))" % (system,))


# ---- options ------------------------------------------------------------------------------------

_ALIASES = {"wmin": "omega_start", "wmax": "omega_end"}


def _targets(settings):
    """Where a flat option name lives: FrfSettings, then its harmonic balance, continuation and
    corrector options (the C++ names; no two share a name)."""
    return [settings, settings.harmonic_balance, settings.continuation, settings.continuation.corrector]


def options():
    """The flat option names frf(), map() and optimize() accept, with their defaults (C++)."""
    s = FrfSettings()
    names = {}
    for target in _targets(s):
        for n in _fields(target):
            if n not in ("harmonic_balance", "continuation", "corrector", "stability_options", "stability"):
                names[n] = getattr(target, n)
    names["stability"] = "off"
    return names


def _set_option(settings, name, value):
    name = _ALIASES.get(name, name)
    for target in _targets(settings):
        if name in _fields(target) and name not in ("harmonic_balance", "continuation", "corrector"):
            _assign(target, name, value)
            return
    raise ValueError("unknown option '%s': allowed %s (and wmin, wmax, stability, outputs, settings)" %
                     (name, ", ".join(sorted(options()))))


def _check_frequencies(settings):
    """`at` named as Python prints it; every other range is the library's (FrfSettings.validate)."""
    for w in settings.at:
        if not (_math.isfinite(w) and w > 0):
            raise ValueError("at = %r is out of range: allowed frequencies > 0" % (w,))
    if len(set(settings.at)) != len(settings.at):
        raise ValueError("at = %r lists a frequency more than once: allowed distinct frequencies" % (list(settings.at),))
    settings.validate()


_CHOICES = ("omega_start", "omega_end", "harmonics", "time_samples", "modes", "odd_harmonics", "jacobian", "formulation")


def _settings(system, settings, outputs, stability, values):
    """FrfSettings for system: `settings` as given, else hbf frf's for it (the library's
    frf_settings: a TOML file's [frequency] and [solver], the keyword arguments among wmin, wmax,
    harmonics, time_samples, modes, odd_harmonics, jacobian, formulation and exact over them, and the automatic
    choices for the rest: the exact polish on the lowest frequency, H); then the other flat
    options `values` and outputs, stability on top."""
    _check_system(system)
    values = dict(values)
    exact = None
    if "exact" in values:
        exact = bool(values.pop("exact"))
        refusal = _core.exact_polish_refusal(system)
        if exact and refusal:
            raise ValueError("exact = True: %s (use exact=False)" % refusal)
    if settings is None:
        given, names = FrfSettings(), []
        for name in [n for n in values if _ALIASES.get(n, n) in _CHOICES]:
            _set_option(given, name, values.pop(name))  # its type checked as any option's
            names.append(_ALIASES.get(name, name))
        s = _core.frf_settings(system, given, names, exact)
    else:
        s = _copy(settings, FrfSettings)
        if exact is not None:
            s.exact = exact
    if outputs is not None:
        s.outputs = _outputs(system, outputs)
    elif not s.outputs:
        s.outputs = system.outputs or [Output.dof(i) for i in range(system.dofs)]
    for o in s.outputs:
        if o.terms and max(i for i, _ in o.terms) >= system.dofs:
            raise ValueError("outputs: '%s' names a DOF beyond the system's %d" % (o.name, system.dofs))
    for name, value in values.items():
        _set_option(s, name, value)
    if stability is not None and stability is not False and stability != "off":
        method = "both" if stability is True or stability == "on" else stability
        s.stability_options.method = method
        refusal = _core.stability_refusal(system)
        if refusal:
            raise ValueError("stability = %r: %s" % (stability, refusal))
        s.stability = True
    elif stability is not None:
        s.stability = False
    _check_frequencies(s)
    return s


# ---- results ------------------------------------------------------------------------------------

def _array(values, kind):
    if kind == "text":
        return _np.array(["" if v is None else v for v in values], dtype=str)
    if kind == "integer" and all(v is not None for v in values):
        return _np.array(values, dtype=_np.int64)
    return _np.array([_math.nan if v is None else v for v in values], dtype=float)


class Table:
    """Columns of a result as NumPy arrays, named as the hbf command's CSV columns.

    ``t.name`` or ``t["name"]`` is a column (numbers: float64 with NaN for an empty field;
    counts: int64; words: str); ``t.columns`` lists the names in order and ``t.meaning`` says
    what each is (the same texts as the command's --help).
    """

    def __init__(self, columns):
        self.columns = [c[0] for c in columns]
        self.meaning = {c[0]: c[1] for c in columns}
        self._data = {c[0]: _array(c[3], c[2]) for c in columns}

    def __getattr__(self, name):
        data = self.__dict__.get("_data")
        if data is not None and name in data:
            return data[name]
        raise AttributeError("%s has no column or attribute '%s' (columns: %s)" %
                             (type(self).__name__, name, ", ".join(self.__dict__.get("columns", []))))

    def __getitem__(self, name):
        return self._data[name]

    def __contains__(self, name):
        return name in self._data

    def __len__(self):
        return len(next(iter(self._data.values()))) if self._data else 0

    def keys(self):
        return list(self.columns)

    def to_dict(self):
        """{column name: array}, in column order."""
        return {n: self._data[n] for n in self.columns}

    def __dir__(self):
        return list(super().__dir__()) + list(self.columns)

    def __repr__(self):
        shown = ", ".join(self.columns[:6]) + (", ..." if len(self.columns) > 6 else "")
        status = getattr(self, "status", None)
        return "<hbfriction.%s: %d rows%s, %d columns (%s)>" % (
            type(self).__name__, len(self), ", " + status if isinstance(status, str) else "", len(self.columns), shown)


class ModeResult(Table):
    """A nonlinear mode (modes()): one row per backbone point with hbf modes' columns (``a``,
    ``w``, ``xi``, ``zeta``, ...), and ``linear`` (the stuck mode followed: ``mode_index``
    0-based, ``omega``, ``zeta``, ``shape``, the slip onset), ``amplitude_min`` and
    ``amplitude_max`` (the range followed), ``harmonics``, ``formulation``, ``status``,
    ``errors``, ``warnings``, ``notes``, ``seconds`` and, with synthesis=True, ``synthesis``."""

    def __repr__(self):
        a = self["a"] if "a" in self else []
        span = (", a %.3g..%.3g" % (a[0], a[-1])) if len(a) else ""
        return "<hbfriction.ModeResult: mode_index %d, %d points%s, %s>" % (
            self.linear["mode_index"], len(self), span, self.status)


def _judge(status, messages, what):
    if status != "completed":
        _warnings.warn("%s is %s: %s" % (what, status, "; ".join(messages) or "see its status"),
                       IncompleteResultWarning, stacklevel=3)


class Branch(Table):
    """An FRF: one row per point (the branch in order, then the `at` samples), the columns of
    hbf frf's CSV (``w``, ``y1_max``, ..., ``stability_margin``; see ``meaning``).

    ``metadata``: hbf frf --summary's JSON as a dict (parameters, solver statistics, peaks, folds,
    transitions, exact polish, stability, status, message, errors, warnings, notes).
    ``status``: completed, incomplete (capped, out of range, unlocated transitions, energy balance)
    or failed (a stalled continuation, a failed polish); ``errors``, ``warnings`` and ``notes`` say
    why, as hbf frf does on standard error. ``settings``: the FrfSettings used.
    """

    def __init__(self, run, settings):
        Table.__init__(self, run.columns)
        self._run = run
        self.settings = settings
        self.metadata = _json.loads(run.summary)
        self.status = run.status
        self.errors = list(run.errors)
        self.warnings = list(run.warnings)
        self.notes = list(run.notes)
        self.seconds = run.seconds
        self.interfaces = []  # the system's meshed interfaces (frf() sets them: interface_states)

    @property
    def peaks(self):
        """The peaks (JSON summary): list of dicts with w, output, y_max, branch, refined."""
        return self.metadata.get("peaks", [])

    @property
    def folds(self):
        return self.metadata.get("folds", [])

    @property
    def transitions(self):
        return self.metadata.get("transitions", [])

    @property
    def peak(self):
        """The largest peak of the first output: dict(value, w, state) (state: bounded, unbounded,
        incomplete or failed)."""
        return self._run.peak

    def per_contact(self, column):
        """A per-contact column of every contact as a 2-D array (rows x contacts): column_c<i>
        (stick_fraction, regime, separated_fraction, normal_force_mean, normal_force_amp, energy),
        or the column itself for one contact."""
        if column in self._data:
            return self._data[column][:, None]
        names = []
        while "%s_c%d" % (column, len(names) + 1) in self._data:
            names.append("%s_c%d" % (column, len(names) + 1))
        if not names:
            raise KeyError("%s: no per-contact column (stick_fraction, regime, separated_fraction, normal_force_mean, "
                           "normal_force_amp, energy)" % column)
        return _np.stack([self._data[n] for n in names], axis=1)

    def interface_states(self, interface=0):
        """The nodes of a meshed interface (index or name; System.interfaces) along the FRF: a dict
        with name, first and count, the per-node arrays (rows x nodes) stick_fraction and
        separated_fraction (share of the period open; 0 for laws without a normal direction),
        slip_fraction (the rest), normal_force_mean, normal_force_amp and energy (where the law has
        them), and the node-averaged shares stuck_share, slip_share, open_share (rows; the CSV's
        ``*_share_i<k>`` columns)."""
        found = [f for k, f in enumerate(self.interfaces) if interface in (k, f["name"])]
        if not found:
            raise KeyError("interface %r: the FRF's system has %s" % (
                interface, ", ".join("%d (%r)" % (k, f["name"]) for k, f in enumerate(self.interfaces)) or "none"))
        f = found[0]
        nodes = slice(f["first"], f["first"] + f["count"])
        out = dict(f)
        out["stick_fraction"] = self.per_contact("stick_fraction")[:, nodes]
        try:
            out["separated_fraction"] = self.per_contact("separated_fraction")[:, nodes]
        except KeyError:
            out["separated_fraction"] = _np.zeros_like(out["stick_fraction"])
        out["slip_fraction"] = _np.clip(1.0 - out["stick_fraction"] - out["separated_fraction"], 0.0, 1.0)
        for column in ("normal_force_mean", "normal_force_amp", "energy"):
            try:
                out[column] = self.per_contact(column)[:, nodes]
            except KeyError:
                pass
        out["stuck_share"] = out["stick_fraction"].mean(axis=1)
        out["open_share"] = out["separated_fraction"].mean(axis=1)
        out["slip_share"] = _np.clip(1.0 - out["stuck_share"] - out["open_share"], 0.0, 1.0)
        return out

    def coefficients(self):
        """The harmonic-balance unknowns of every point (harmonic_balance.hpp layout), one array per row."""
        return [_np.array(x) for x in self._run.coefficients]

    def csv(self):
        """The CSV text hbf frf writes for this FRF (identical, byte for byte, for the same input)."""
        return self._run.csv()

    def write_csv(self, path):
        """Writes csv() to path under hbf's output policy: atomically, a symlink, device or FIFO is
        never replaced by a file (ValueError naming the problem)."""
        _core.write_text(str(path), self.csv())

    def write_summary(self, path):
        """Writes the JSON summary (hbf frf --summary) to path, under the same policy."""
        _core.write_text(str(path), self._run.summary)

    def __repr__(self):
        return "<hbfriction.Branch: %d points, %s, %d peak(s)>" % (len(self), self.status, len(self.peaks))


def frf(system, settings=None, *, outputs=None, stability=None, time_limit=0, **options):
    """The frequency response of `system` (hbf frf): pseudo-arclength continuation of the
    harmonic-balance solutions over [omega_start, omega_end], the exact polish where it applies,
    the peaks refined. Returns a Branch.

    system: absorber(), load() or System(...). settings: an FrfSettings taken as given (else hbf
    frf's defaults: exact polish for coulomb and jenkins on models it covers, H automatic (10 with
    the polish, 20 for coulomb and coulomb-reg, 10 otherwise), a TOML file's own settings).
    outputs: DOF indices (0-based), Output objects or (name, row) pairs (default: the system's,
    else every DOF). stability: False/"off" (default), True/"on"/"both", "hill" or "monodromy".
    options: any field of FrfSettings, HarmonicBalanceOptions, ContinuationOptions or
    CorrectorOptions by its C++ name, e.g. harmonics=20, omega_start=0.8 (or wmin=0.8),
    omega_end=1.3, exact=False, at=[1.0, 1.1], tolerance=1e-10, max_amplitude=100 (see options()).
    time_limit: seconds (0: none) after which the continuation stops; the points so far are the
    result, its status stopped (an IncompleteResultWarning). An interrupt (Ctrl-C) does the same.
    """
    s = _settings(system, settings, outputs, stability, options)
    branch = Branch(_core.compute_frf(system, s, _real("time_limit", time_limit)), s)
    branch.interfaces = system.interfaces
    _judge(branch.status, branch.errors + branch.warnings, "the FRF")
    return branch


class Solution:
    """One harmonic-balance solution (hbf loop): omega, the metrics (y_max, y_amp1 per DOF, y_max
    NaN for a DOF outside the system's outputs: not computed, each output's maximum over a period costs a fine grid;
    output_max, output_amp1 per output, stick_fraction and regime of contact 1, stick_fractions and
    regimes of every contact (lists, in order), energy, energy_error), the
    coefficients (2H + 1 rows: c0, c1, s1, ..., one column per DOF), and one period of signals of
    the chosen contact: t, y (samples x DOFs), q, v, f (the law's force), phi (stick indicator:
    sticks where < 0), f_series (f's H-harmonic series)."""

    def __init__(self, d):
        self.omega = d["omega"]
        self.harmonics = d["harmonics"]
        self.x = _np.array(d["x"])
        self.iterations = d["iterations"]
        self.residual = d["residual"]
        flat, shape = d["coefficients"]
        self.coefficients = _np.array(flat).reshape(shape)
        for key in ("y_max", "y_amp1", "output_max", "output_amp1"):
            setattr(self, key, _np.array(d[key], dtype=float))
        for key in ("stick_fraction", "regime", "stick_fractions", "regimes", "energy", "input_energy",
                    "viscous_energy", "energy_error"):
            setattr(self, key, d[key])
        sig = d["signals"]
        self.t = _np.array(sig["t"])
        flat, shape = sig["y"]
        self.y = _np.array(flat).reshape(shape)
        for key in ("q", "v", "f", "phi", "f_series"):
            setattr(self, key, _np.array(sig[key]))
        self.stick = self.phi < 0

    def __repr__(self):
        return "<hbfriction.Solution at w = %s: %s, y_max = %s>" % (_core.format_number(self.omega), self.regime,
                                                                    _np.array2string(self.y_max, precision=6))


def solve_at(system, omega, *, omega_from=None, contact=0, harmonics=None, time_samples=None, odd_harmonics=None,
             formulation=None, modes=None, **options):
    """The harmonic-balance solution at omega reached by following the branch from omega_from
    (default: the system's omega_start, 0.5; from 0.9 omega when omega <= omega_from), as hbf loop.
    harmonics etc.: as frf (automatic H without the polish). contact: whose signals (0-based).
    options: ContinuationOptions and CorrectorOptions fields. Raises SolveError when the branch
    stops before omega."""
    _check_system(system)
    given, names = FrfSettings(), []
    for name, value in (("harmonics", harmonics), ("time_samples", time_samples), ("odd_harmonics", odd_harmonics),
                        ("modes", modes)):
        if value is not None:
            _assign(given.harmonic_balance, name, value)
            names.append(name)
    s = _core.frf_settings(system, given, names, False)  # as hbf loop: the automatic H without the polish
    hb = s.harmonic_balance
    if formulation is not None:
        _assign(hb, "formulation", formulation)
    co = ContinuationOptions()
    for name, value in options.items():
        name = _ALIASES.get(name, name)
        if name in _fields(co) and name != "corrector":
            _assign(co, name, value)
        elif name in _fields(co.corrector):
            _assign(co.corrector, name, value)
        else:
            raise ValueError("solve_at: unknown option '%s': allowed the fields of ContinuationOptions and "
                             "CorrectorOptions" % name)
    _check_frequencies(s)
    start = omega_from if omega_from is not None else system.file_settings.get("omega_start", 0.5)
    omega = _real("omega", omega)
    start = _real("omega_from", start)
    d = _core.solve_at(system, omega, start, hb, co, _integer("contact", contact))
    if not d["found"]:
        raise SolveError("no solution at w = %s: the branch from w = %s stopped: %s" %
                         (_core.format_number(omega), _core.format_number(start if omega > start else 0.9 * omega),
                          d["message"]))
    solution = Solution(d)
    if solution.energy_error > d["energy_limit"]:
        _warnings.warn("the solution at w = %s fails the energy balance (relative error %g, allowed %g)" %
                       (_core.format_number(omega), solution.energy_error, d["energy_limit"]),
                       IncompleteResultWarning, stacklevel=2)
    return solution


def _responses_table(columns, details):
    """A Table of hbf timeint's columns with ``responses``: per row a dict, its signals as arrays."""
    table = Table(columns)
    table.responses = []
    for d in details:
        r = dict(d)
        for key in ("y", "velocity", "friction_force"):
            flat, shape = d[key]
            r[key] = _np.array(flat).reshape(shape)
        r["t"] = _np.array(d["t"])
        r["state"] = _np.array(d["state"])
        table.responses.append(r)
    return table


def timeint(system, w, *, outputs=None, options=None, method=None, symmetric=False, time_limit=0, **values):
    """Periodic steady states by time integration (hbf timeint): at each frequency of w (a number
    or a sequence, swept in the order given, each from the previous final state, the first from
    the stuck linear state). method: adams (default) or bdf (CVODE), or exact (coulomb, jenkins
    and law unilateral on massless contact nodes: the event-exact solver, steady state to
    steady_tolerance if given, else 1e-12; law unilateral's first orbit from rest, each next one
    from the secant through the previous two). symmetric (method exact, law unilateral's 3D
    contacts on a structure with a mirror symmetry; hbf timeint --symmetric on): each orbit
    solved among the mirror-symmetric states (where nodes stick all period: the symmetric member
    of the family Newton reaches from the start projected onto them); raises where the structure
    has no such symmetry. time_limit: seconds (0: none) after which the sweep stops, as on Ctrl-C:
    the frequencies done are the result (status incomplete, ``stopped`` True, a warning naming
    where), the one under way is not.
    options/values: TimeIntegrationOptions (C++ names, e.g. relative_tolerance=1e-9,
    max_periods=500). Returns a Table with hbf timeint's columns, plus ``responses`` (per
    frequency a dict with converged, message, state, t, y, velocity, friction_force: one period
    of samples; method exact also max_multiplier and multiplier_accuracy, above 1 by less than
    which the largest multiplier leaves the stability uncertain) and status/errors/warnings: failed where a point did not converge, incomplete
    where converged points fail the energy balance (as hbf timeint's exit codes 1 and 3); ``notes``
    as hbf timeint's (method exact: the unstable orbits, those of unknown or uncertain stability, those Newton
    left at the flow's rounding above the tolerance)."""
    _check_system(system)
    o = TimeIntegrationOptions() if options is None else _copy(options, TimeIntegrationOptions)
    exact_tolerance = 1e-12
    for name, value in values.items():
        if name not in _fields(o):
            raise ValueError("timeint: unknown option '%s': allowed %s" % (name, ", ".join(_fields(o))))
        _assign(o, name, value)
    if "steady_tolerance" in values or options is not None:
        exact_tolerance = o.steady_tolerance
    if method is not None and method != "exact":
        o.method = method
    # hbf timeint's ranges for what would otherwise only be limited by memory or time.
    if not 8 <= o.samples_per_period <= 65536:
        raise ValueError("samples_per_period = %d is out of range: allowed 8..65536" % o.samples_per_period)
    if not 1 <= o.max_periods <= 1000000:
        raise ValueError("max_periods = %d is out of range: allowed 1..1000000" % o.max_periods)
    o.outputs = _outputs(system, outputs) if outputs is not None else (
        system.outputs or [Output.dof(i) for i in range(system.dofs)])
    omegas = _reals("w", w)
    columns, details, verdict = _core.timeint(system, omegas, o, method == "exact", exact_tolerance, bool(symmetric),
                                              _real("time_limit", time_limit))
    table = _responses_table(columns, details)
    table.stopped = verdict["stopped"]
    table.status = verdict["status"]
    table.errors = verdict["errors"]
    table.warnings = verdict["warnings"]
    table.notes = verdict["notes"]
    _judge(table.status, table.errors + table.warnings, "the time integration")
    return table


def exact_branch(system, wmin, wmax, *, points=101, outputs=None, tolerance=1e-12, time_limit=0):
    """The branch of exact periodic orbits from wmin followed through its folds until it leaves
    [wmin, wmax] (hbf timeint --method exact --sweep branch; coulomb, jenkins, laws unilateral and
    elastic): each point the exact orbit at the w predicted along the branch, its steps at most
    those of `points` points on a flat branch (adapted), at most 20 points points.
    tolerance: Newton's on the period map; time_limit: seconds (0: none; then, or on Ctrl-C, the
    points so far with status stopped). Returns a Table with hbf timeint's columns in branch
    order, plus ``responses`` (as timeint's, with each orbit's max_multiplier), ``folds`` (per
    turn in w a dict: w, the parabola's vertex through the exact orbits about it, and point, the
    row of the turn), ``corners`` (w where the branch's tangent turns), ``branch_status``
    (completed, incomplete, stopped, failed) and ``message`` (where and why it ended), and
    status/errors/warnings as hbf timeint's exit codes (an IncompleteResultWarning unless
    completed); ``notes`` as hbf timeint's (unstable orbits, unknown or uncertain stability, orbits at the
    flow's rounding above the tolerance)."""
    _check_system(system)
    selected = _outputs(system, outputs) if outputs is not None else []
    columns, details, verdict = _core.exact_branch(system, _real("wmin", wmin), _real("wmax", wmax),
                                                  _integer("points", points), selected, _real("tolerance", tolerance),
                                                  _real("time_limit", time_limit))
    table = _responses_table(columns, details)
    table.folds = verdict["folds"]
    table.corners = verdict["corners"]
    table.branch_status = verdict["status"]
    table.message = verdict["message"]
    errors = list(verdict["errors"])
    warnings = list(verdict["warnings"])
    if verdict["status"] == "failed":
        errors.insert(0, verdict["message"])
    elif verdict["status"] != "completed":
        warnings.insert(0, verdict["message"])
    table.errors = errors
    table.warnings = warnings
    table.notes = verdict["notes"]
    table.status = "failed" if errors else "incomplete" if warnings else "completed"
    _judge(table.status, table.errors + table.warnings, "the exact branch")
    return table


def modes(system, amplitude_min=None, amplitude_max=None, *, mode_index=None, near=None, harmonics=None,
          time_samples=None, formulation=None, modes=None, outputs=None, tolerance=None, max_step=None, max_points=None,
          synthesis=False, exact_check=False, start_frequency=None, mode=None, time_limit=0):
    """A nonlinear mode by the extended periodic motion concept (hbf modes): frequency and modal
    damping ratio against the modal amplitude a (the M-norm of the first harmonic), followed from
    amplitude_min to amplitude_max from the stuck structure's linear mode `mode_index` (0-based by
    ascending frequency, default 0) or the one nearest the frequency `near`. Without
    amplitude_min and amplitude_max the range is a tenth to a hundred times the slip onset (the
    largest amplitude at which a stuck motion exists, ``linear``'s ``slip_onset``; the contact
    that slips or opens there, ``slip_contact`` and ``slip_opens``; with the sliders where the
    static load leaves them, the first contact's limit ``slip_onset_static`` of contact
    ``slip_contact_static``), as hbf modes chooses it. `mode` (1-based) is the former
    name of the index: deprecated, it still works with a DeprecationWarning. harmonics, time_samples: as frf (automatic H from
    the laws). formulation: "full", "condensed" or "automatic" (default: full up to 256 unknowns
    N (2H + 1) without modes, else condensed), modes: the condensed formulation's modal receptance
    (0: the direct solve), as hbf modes --formulation, --modes. Returns a Table with hbf modes' columns (a, w, xi, zeta, zeta_energy, energies, the
    outputs' amplitudes, per-contact shares, harmonic content), plus ``linear`` (dict: mode, omega,
    zeta, shape of the stuck mode; a sector model's mode is the travelling wave of its engine order,
    its ``shape`` complex on every DOF of the sector), ``harmonics``, ``formulation`` and ``modes`` used, ``seconds`` and status/errors/warnings: incomplete where the
    backbone stops before amplitude_max or fails the energy balance, or (synthesis=True) where the
    synthesised response is cut at the backbone's last point (its peak lies beyond amplitude_max)
    or empty (below amplitude_min) (as hbf modes' exit code 3); raises SolveError where its
    first point does not converge (no backbone: hbf modes' exit code 1). synthesis=True adds ``synthesis``: a
    Table with hbf modes --synthesis-out's columns, the response to the system's excitation
    synthesised from the mode. exact_check=True checks every point against the event-exact solver
    (exact Coulomb and Jenkins; hbf modes --exact-check): columns exact_w, exact_xi, exact_gap (NaN
    where not checked) and ``notes`` with the largest gap. The first point starts from the linear
    limit (the stuck mode, or where the stuck structure is damped its damped mode: ``linear``'s
    ``linear_omega``, ``linear_xi``), followed up from the linear regime where amplitude_min lies
    beyond it (``linear["start"]``: "linear", "run-up", "unchecked" (a warning), "given");
    start_frequency (> 0) gives the first point's frequency guess instead (not checked).
    time_limit: seconds (0: none) after which the backbone stops; the points so far are the
    result, its status stopped (an IncompleteResultWarning). An interrupt (Ctrl-C) does the same."""
    _check_system(system)
    if mode is not None:
        if mode_index is not None:
            raise ValueError("modes: give mode_index (0-based) alone: mode (1-based) is its deprecated former name")
        _warnings.warn("modes: mode= (1-based) is deprecated: use mode_index= (0-based, as every index in "
                       "hbfriction): mode=%r is mode_index=%r" % (mode, mode - 1 if isinstance(mode, int) else mode),
                       DeprecationWarning, stacklevel=2)
        index = _integer("mode", mode)
        if index < 1:
            raise ValueError("mode = %d is out of range: allowed >= 1 (1-based; deprecated: use mode_index, 0-based)" % index)
    elif mode_index is not None:
        index = _integer("mode_index", mode_index)
        if index < 0:
            raise ValueError("mode_index = %d is out of range: allowed >= 0 (0-based, by ascending frequency)" % index)
        index += 1
    else:
        index = None
    if index is not None and near is not None:
        raise ValueError("modes: mode_index and near cannot both be given: the mode by its index or by a frequency")
    if (amplitude_min is None) != (amplitude_max is None):
        raise ValueError("modes: give amplitude_min and amplitude_max together, or neither (the range is then chosen "
                         "from the contacts' slip onset)")
    given, names = FrfSettings(), []
    for name, value in (("harmonics", harmonics), ("time_samples", time_samples), ("modes", modes)):
        if value is not None:
            _assign(given.harmonic_balance, name, value)
            names.append(name)
    s = _core.frf_settings(system, given, names, False)  # as hbf modes: the automatic H without the polish
    if formulation is not None:
        _assign(s.harmonic_balance, "formulation", formulation)
    if s.harmonic_balance.modes > 0 and str(s.harmonic_balance.formulation) == "full":
        raise ValueError("modes: modes = %d (the modal receptance) needs the condensed formulation: allowed "
                         "formulation='condensed' or 'automatic', or modes=0" % s.harmonic_balance.modes)
    d = _core.mode_defaults()
    o = _outputs(system, outputs) if outputs is not None else (system.outputs or [Output.dof(i) for i in range(system.dofs)])
    for name, flag in (("synthesis", synthesis), ("exact_check", exact_check)):
        if not isinstance(flag, (bool, _np.bool_)):
            raise TypeError("%s = %r: expected True or False" % (name, flag))
    columns, details, verdict = _core.modes(
        system, s.harmonic_balance, d["mode"] if index is None else index,
        _real("near", 0.0 if near is None else near),
        0.0 if amplitude_min is None else _positive("amplitude_min", amplitude_min),
        0.0 if amplitude_max is None else _positive("amplitude_max", amplitude_max), _real("tolerance", d["tolerance"] if tolerance is None else tolerance),
        _real("max_step", d["max_step"] if max_step is None else max_step),
        _integer("max_points", d["max_points"] if max_points is None else max_points), o,
        bool(synthesis), bool(exact_check), _real("start_frequency", 0.0 if start_frequency is None else start_frequency),
        _real("time_limit", time_limit))
    if verdict["status"] == "failed" and not columns[0][3]:
        # No point at all (the first one did not converge): nothing to return.
        raise SolveError("modes: no backbone: " + "; ".join(verdict["errors"] + verdict["warnings"] + [details["message"]]))
    table = ModeResult(columns)
    table.synthesis = Table(details["synthesis"]) if synthesis else None
    linear = dict(details)
    linear["shape"] = _np.array(details["shape"])
    if "shape_imag" in details:  # a sector's travelling wave
        linear["shape"] = linear["shape"] + 1j * _np.array(details["shape_imag"])
    linear["mode_index"] = details["mode"] - 1
    table.linear = {k: linear[k] for k in ("mode_index", "mode", "omega", "zeta", "shape", "start", "linear_omega",
                                           "linear_xi", "slip_onset", "slip_contact", "slip_opens",
                                           "slip_onset_static", "slip_contact_static")}
    table.amplitude_min = details["amplitude_min"]
    table.amplitude_max = details["amplitude_max"]
    table.harmonics = details["harmonics"]
    table.formulation = details["formulation"]
    table.modes = details["modes_used"]
    table.seconds = details["seconds"]
    table.message = details["message"]
    table.status = verdict["status"]
    table.errors = verdict["errors"]
    table.warnings = verdict["warnings"]
    table.notes = verdict["notes"]
    _judge(table.status, table.errors + table.warnings, "the backbone")
    return table


def analytic(system=None, w=None, *, law=None, parameters=None):
    """The paper's closed forms for the absorber (hbf analytic): full stick, full slip (equivalent
    viscous), the limit friction coefficient and Den Hartog's optimum, at the frequencies w.
    system: an absorber() System (its law and parameters), or give law and parameters
    (AbsorberParameters). Returns a Table with hbf analytic's columns (empty where no solution)."""
    if system is not None:
        _check_system(system)
        if system.absorber is None:
            raise ValueError("analytic: the closed forms are those of the paper's absorber: give absorber(...)")
        parameters, law = system.absorber, system.law
    if law is None:
        law = "coulomb"
    if law not in ("coulomb", "dahl", "lugre"):
        raise ValueError("analytic: law = '%s' has no closed form here: allowed coulomb, dahl, lugre" % law)
    if parameters is None:
        parameters = AbsorberParameters()
    if w is None:
        raise ValueError("analytic: w (the frequencies) is required")
    omegas = _reals("w", w)
    return Table(_core.analytic(parameters, law, omegas))


def nodal_diameters(system, harmonics=10):
    """The linear nodal-diameter families of the wheel whose sector `system` is (a system file
    with a [cyclic] table; hbf nodal-diameters): a Table with one row per nodal diameter and mode,
    the natural frequencies released and stuck, and the harmonics up to `harmonics` of an
    engine-order response that meet each nodal diameter (excited_by)."""
    _check_system(system)
    if system.cyclic is None:
        raise ValueError("nodal_diameters: the system is not a sector (no [cyclic] table)")
    return Table(_core.nodal_diameters(system, _integer("harmonics", harmonics)))


class OptimizeResult:
    """The result of optimize(): status (converged, at_bound, budget, unbounded, failed),
    parameter (the best p), peak (dict value, w, state), peaks, bracket, trace (a dict of arrays:
    parameter, peak, w, state, status, phase, seconds; one entry per FRF), message, summary;
    the verdict as hbf optimize's exit code: outcome (completed, incomplete, failed), errors,
    warnings, notes."""

    def __init__(self, d):
        self.__dict__.update({k: v for k, v in d.items() if k != "trace"})
        trace = d["trace"]  # empty with method tracking
        self.trace = {k: _np.array([t[k] for t in trace]) for k in
                      ("parameter", "peak", "w", "state", "status", "phase", "seconds")}

    def __repr__(self):
        return "<hbfriction.OptimizeResult: %s>" % self.summary


def optimize(system, lower, upper, *, settings=None, search=None, outputs=None, scan_points=None,
             max_evaluations=None, threads=None, method="golden", **options):
    """Minimises the largest peak of the first output of frf(system(p)) over p in [lower, upper]
    (hbf optimize): a log-spaced scan on threads, then a golden-section search in log p
    (method="golden"), or the peaks followed from the best scan value to its neighbours
    (method="tracking", hbf optimize --method tracking: the optimum where two peaks are equal or
    one peak is smallest, checked by an FRF; the result's trace is then empty, and kind,
    check_peak, restarts, solves, frfs and tracks (as track()'s curves) say what it did).

    system: a callable p -> System (e.g. lambda mu: absorber("lugre", mu=mu)); its ValueError
    for a p makes that FRF failed, as an out-of-range parameter in hbf optimize. search: an
    OptimizeOptions (scan_points, tolerance of the search, max_evaluations, threads), or those
    by keyword (scan_points, max_evaluations, threads). options: the FRF's, as frf() (tolerance is
    the corrector's). The FRF settings are hbf frf's defaults for system(sqrt(lower upper))."""
    if not callable(system):
        raise TypeError("system: a callable p -> System is required")
    if not (_math.isfinite(lower) and _math.isfinite(upper) and 0 < lower < upper):
        raise ValueError("lower = %r, upper = %r are out of range: allowed 0 < lower < upper, finite" % (lower, upper))
    sample = system(_math.sqrt(lower * upper))
    s = _settings(sample, settings, outputs, None, options)
    o = OptimizeOptions() if search is None else _copy(search, OptimizeOptions)
    o.lower, o.upper = float(lower), float(upper)
    for name, value in (("scan_points", scan_points), ("max_evaluations", max_evaluations), ("threads", threads)):
        if value is not None:
            _assign(o, name, value)
    if method not in ("golden", "tracking"):
        raise ValueError("method = %r is not known: allowed golden or tracking" % (method,))
    if method == "tracking":
        if max_evaluations is not None:
            raise ValueError("max_evaluations bounds the golden-section search: method tracking computes the scan "
                             "and a few checks")
        d = _core.optimize_tracking(system, s, o)
        d["trace"] = []
        d["tracks"] = [TrackResult(t) for t in d["tracks"]]
        result = OptimizeResult(d)
    else:
        result = OptimizeResult(_core.optimize(system, s, o))
    if result.status != "converged":
        _warnings.warn("the optimisation is %s: %s" % (result.status, result.summary), IncompleteResultWarning,
                       stacklevel=2)
    elif result.outcome != "completed":  # converged, but doubtful (the library's verdict, as hbf optimize's)
        _warnings.warn("the optimisation is %s: %s" % (result.outcome, "; ".join(result.warnings)),
                       IncompleteResultWarning, stacklevel=2)
    return result


class TrackCurve:
    """One followed feature of track(): id, label, status (completed, vanished, left_range,
    amplitude_cap, point_budget, failed, stopped), message (why it ended), contact and boundary (boundary
    curves), and its points as arrays: p, w, value (the output's max over one period), kind
    (start, step, at, exchange, search, end), regime, curvature (Y'' w^2 / Y at a peak), corner."""

    def __init__(self, d):
        for k in ("id", "label", "status", "message", "contact", "boundary"):
            setattr(self, k, d[k])
        for k in ("p", "w", "value", "curvature"):
            setattr(self, k, _np.array(d[k], dtype=float))
        for k in ("kind", "regime"):
            setattr(self, k, _np.array(d[k], dtype=str))
        self.corner = _np.array(d["corner"], dtype=bool)

    def __len__(self):
        return len(self.p)

    def __repr__(self):
        return "<hbfriction.TrackCurve %d: %s, %s, %d points>" % (self.id, self.label, self.status, len(self))


class TrackResult:
    """The result of track(): feature, exact (solved by the event-exact solver), curves (a
    TrackCurve each), events (dicts: kind exchange, vanished or born; p, w, value, curve, other,
    other_w), solves, frfs, seconds, summary; the verdict as hbf track's exit code: outcome,
    errors, warnings, notes."""

    def __init__(self, d):
        self.__dict__.update({k: v for k, v in d.items() if k != "curves"})
        self.curves = [TrackCurve(c) for c in d["curves"]]

    def __repr__(self):
        return "<hbfriction.TrackResult: %s>" % self.summary


def track(system, p_start, p_end, *, feature="peak", omega=None, at=None, max_step=0.05, min_step=1e-7,
          max_points=5000, contact=None, settings=None, outputs=None, time_limit=0, **options):
    """Follows the resonance peaks of the first output (feature="peak"), the stick-slip
    boundaries of the contacts (feature="boundary") or the folds of the harmonic-balance FRF
    through their cusps (feature="fold") of system(p) from p_start to p_end (hbf
    track): the features of an FRF at p_start, each followed with a predictor in p and re-located
    at each value (peaks by Newton on dY/dw = 0, boundaries by bisection on the regime); exact
    for coulomb and jenkins contacts (the event-exact solver), harmonic balance otherwise.

    system: a callable p -> System. omega: follow only the feature nearest to it at p_start
    (within 10 %). at: values of p where every curve gets a point. max_step, min_step: steps in p
    relative to the range, abs(p_end - p_start). contact: boundary only, 0-based (None: every contact's).
    options: the FRF's, as frf() (wmin, wmax, harmonics, ...). time_limit: seconds (0: none)
    after which the curves stop where they are (status stopped); an interrupt (Ctrl-C) does the
    same. Returns a TrackResult; warns (IncompleteResultWarning) when it is not completed."""
    if not callable(system):
        raise TypeError("system: a callable p -> System is required")
    for name, v in (("p_start", p_start), ("p_end", p_end)):
        if not (isinstance(v, (int, float)) and _math.isfinite(v)):
            raise ValueError("%s = %r is out of range: allowed a finite number" % (name, v))
    sample = system(float(p_start))
    _check_system(sample)
    s = _settings(sample, settings, outputs, None, options)
    if not isinstance(feature, str):
        raise TypeError("feature = %r: expected 'peak', 'boundary' or 'fold'" % (feature,))
    r = TrackResult(_core.track(system, s, feature, float(p_start), float(p_end),
                                float("nan") if omega is None else _real("omega", omega),
                                [] if at is None else [_real("at", v) for v in at], _real("max_step", max_step),
                                _real("min_step", min_step), _integer("max_points", max_points),
                                -1 if contact is None else _integer("contact", contact), _real("time_limit", time_limit)))
    if r.outcome != "completed":
        _warnings.warn("track is %s: %s" % (r.outcome, "; ".join(r.errors + r.warnings)), IncompleteResultWarning,
                       stacklevel=2)
    return r


class MapResult:
    """The result of map(): values, branches (one Branch per value), and per value the largest
    peak of the first output (peak, w_peak), its state and the FRF's status, as arrays."""

    def __init__(self, values, branches):
        self.values = _np.array(values, dtype=float)
        self.branches = branches
        self.peak = _np.array([b.peak["value"] for b in branches], dtype=float)
        self.w_peak = _np.array([b.peak["w"] for b in branches], dtype=float)
        self.state = _np.array([b.peak["state"] for b in branches], dtype=str)
        self.status = _np.array([b.status for b in branches], dtype=str)

    def __len__(self):
        return len(self.branches)

    def __repr__(self):
        return "<hbfriction.MapResult: %d FRFs, %d completed>" % (len(self), int((self.status == "completed").sum()))


def map(system, values, *, threads=0, settings=None, outputs=None, **options):
    """FRFs of system(v) for every v in values, `threads` at a time (0: every core; hbf map):
    returns a MapResult (a Branch per value and the peaks as arrays). system: a callable
    v -> System, called here for every value before the work starts; options as frf(), the
    settings being hbf frf's defaults for system(values[0])."""
    if not callable(system):
        raise TypeError("system: a callable v -> System is required")
    values = [float(v) for v in values]
    if not values:
        raise ValueError("values: empty: allowed one or more values")
    systems = [system(v) for v in values]
    for s_ in systems:
        _check_system(s_)
    s = _settings(systems[0], settings, outputs, None, options)
    if not (isinstance(threads, int) and threads >= 0):
        raise ValueError("threads = %r is out of range: allowed 0 (every core) or more" % (threads,))
    runs = _core.compute_frfs(systems, s, threads)
    branches = [Branch(r, s) for r in runs]
    bad = [b for b in branches if b.status != "completed"]
    if bad:
        _warnings.warn("%d of %d FRFs are not completed (MapResult.status; each Branch's errors and warnings "
                       "say why)" % (len(bad), len(branches)), IncompleteResultWarning, stacklevel=2)
    return MapResult(values, branches)


def check_output(path):
    """hbf's output policy for a file a script is about to write (output_file.hpp check_outputs): its
    directory exists and is writable, it is not a directory, a socket or a dangling symlink.
    ValueError names the problem."""
    _core.check_output(str(path))
