"""A small named, parametric NLP on CasADi SX: build once, solve many times.

Variables, parameters and constraint rows are declared by name; the problem is compiled once
into an IPOPT ``nlpsol`` and then re-solved with new parameter values, bounds and warm starts
(the way AeroSandbox and ``casadi.Opti`` keep names, without ``Opti``'s per-solve overhead:
the built-in optimize's NLP posed through ``Opti`` takes 10-18 ms of CPU a solve instead of
5-9 ms, the same iterations, ``benchmarks/bench_nlp_opti.py``; docs/architecture.md).
A :class:`Solution` reads values, multipliers and parametric sensitivities by name.

Conventions: every row is ``g <= 0``; variables are scaled, ``physical = ref * scaled``, so the
solver sees O(1) numbers while the caller speaks SI.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

__all__ = ["CompiledNLP", "NLPBuilder", "Row", "Solution"]


class SolveInterrupted(KeyboardInterrupt):
    """IPOPT was stopped from outside mid-solve (CasADi turns an interrupt that arrives during a
    solve into a status, ``NonIpopt_Exception_Thrown``); raised so the interrupt is not lost."""


#: IPOPT statuses that mean the solve was stopped from outside, not that it failed.
INTERRUPTED = ("NonIpopt_Exception_Thrown", "User_Requested_Stop")


@dataclass(frozen=True)
class Row:
    """One constraint row ``g <= 0``: its name, kind, unit and which way relaxing goes.

    ``kind`` is "objective" (epigraph rows), "limit", "requirement" or "geometry"; ``unit`` the
    SI unit of the quantity it bounds; ``relax_sign`` +1 when relaxing means raising the
    allowed value (a limit), -1 when lowering it (a minimum).

    Attributes
    ----------
    name : str
        Row name (``current_x``, ``speed``, ...).
    kind : str
        ``"objective"``, ``"epigraph"``, ``"limit"``, ``"requirement"`` or ``"geometry"``.
    unit : str
        SI unit symbol of the bounded quantity (empty: none).
    relax_sign : float
        +1 or -1, dimensionless: the direction of the bound that relaxes the row.
    """

    name: str
    kind: str
    unit: str = ""
    relax_sign: float = 1.0


@dataclass(frozen=True)
class _Var:
    name: str
    ref: float
    lo: float
    hi: float


class NLPBuilder:
    """Collect named scaled variables, parameters, rows ``g <= 0`` and one objective."""

    def __init__(self) -> None:
        self._vars: list[_Var] = []
        self._xsym: list[Any] = []
        self._params: dict[str, tuple[Any, tuple[int, ...]]] = {}
        self._rows: list[Row] = []
        self._g: list[Any] = []
        self._allowed: list[Any] = []
        self._value: list[Any] = []
        self._dgda: list[Any] = []
        self._f: Any = None
        self._names: set[str] = set()
        self._start: list[Any] = []
        #: auxiliary variables declared with a start (scaled symbol, its scaled start in terms
        #: of the named variables and the parameters alone)
        self._aux: list[tuple[Any, Any]] = []

    def variable(
        self, name: str, ref: float, lo: float = -np.inf, hi: float = np.inf, start: Any = None
    ) -> Any:
        """A scalar variable (bounds in physical units); returns its physical expression.

        ``start``: an expression of the variables declared before and the parameters that
        gives this one's initial value when a solve's start does not name it (an auxiliary
        epigraph variable started where its rows hold).

        Parameters
        ----------
        name : str
            Variable name (its unit suffix says the physical unit).
        ref : float
            Scale: physical = ``ref`` x scaled, in the unit the variable's name carries.
        lo, hi : float
            Bounds, in the unit the variable's name carries.
        start : casadi.SX, optional
            Expression of its initial value, in the unit the variable's name carries.

        Returns
        -------
        casadi.SX
            The physical expression ``ref * scaled``, in the unit the variable's name carries.
        """
        if name in self._names:
            raise ValueError(f"variable {name!r} declared twice")
        s = ca.SX.sym(name)
        self._names.add(name)
        self._vars.append(_Var(name, float(ref), float(lo), float(hi)))
        self._xsym.append(s)
        if start is None:
            self._start.append(s)
        else:
            # a start may read auxiliary variables declared before (an epigraph of lifted
            # terms): read their starts instead, so it is where its rows hold at the start
            start = ca.SX(start) / float(ref)
            if self._aux and ca.depends_on(start, ca.vertcat(*(a for a, _ in self._aux))):
                syms, starts = zip(*self._aux)
                start = ca.substitute([start], list(syms), list(starts))[0]
            self._start.append(start)
            self._aux.append((s, start))
        return s * float(ref)

    def positive_part(self, x: Any, ref: float = 0.1) -> Any:
        """``max(x, 0)`` as epigraph variables where ``x`` depends on the variables.

        Each element becomes a variable ``s >= 0`` (named ``positive_part[<i>]``, ``ref`` its
        scale) with the row ``x - s <= 0`` (kind "epigraph"), started at ``max(x, 0)``: exact
        wherever the optimiser is pushed to make ``s`` small (a cost), smooth where ``max`` has a
        corner. Expressions of the parameters alone stay ``fmax`` (no kink IPOPT moves across),
        and so do vectors (the scenarios of a robust problem).

        Parameters
        ----------
        x : casadi.SX or float
            The expression, in the caller's unit (its name carries it).
        ref : float
            Scale of the epigraph variable, in the unit of ``x`` (its name carries it).

        Returns
        -------
        casadi.SX
            ``max(x, 0)``, in the unit of ``x`` (its name carries it).
        """
        x = ca.SX(x)
        if x.numel() != 1 or not self._xsym or not ca.depends_on(x, ca.vertcat(*self._xsym)):
            # a vector is the tissue scenarios of a robust problem: one corner among many moves
            # the CVaR by 1/N, and lifting each would double the scenario NLP
            return ca.fmax(x, 0.0)
        out = []
        for i in range(x.numel()):
            xi = x[i]
            name = f"positive_part[{sum(v.name.startswith('positive_part[') for v in self._vars)}]"
            s = self.variable(name, ref, 0.0, np.inf, start=ca.fmax(xi, 0.0))
            self.constrain(Row(name, "epigraph"), (xi - s) / ref)
            out.append(s)
        return ca.reshape(ca.vertcat(*out), x.shape[0], x.shape[1])

    def parameter(self, name: str, shape: tuple[int, ...] = ()) -> Any:
        """A parameter of ``shape`` (``()`` scalar, ``(n,)`` vector); returns its symbol.

        Parameters
        ----------
        name : str
            Parameter name (its unit suffix says the unit).
        shape : tuple of int
            ``()`` for a scalar, ``(n,)`` for a vector of n, a count.

        Returns
        -------
        casadi.SX
            The parameter's symbol, in the unit its name carries.
        """
        if name in self._params:
            return self._params[name][0]
        n = int(np.prod(shape)) if shape else 1
        s = ca.SX.sym(name, n)
        self._params[name] = (s, shape)
        return s

    def constrain(
        self,
        row: Row,
        expr: Any,
        allowed: Any = None,
        dg_dallowed: Any = None,
        value: Any = None,
    ) -> None:
        """Add the row ``expr <= 0``; ``value`` the bounded quantity, ``allowed`` its bound and
        ``dg_dallowed`` ∂expr/∂bound (for the sensitivities).

        Parameters
        ----------
        row : Row
            The row's name, kind and unit.
        expr : casadi.SX
            g of the row ``g <= 0``, scaled (dimensionless, O(1)).
        allowed : casadi.SX or float, optional
            The bound, in the unit ``row.unit`` names.
        dg_dallowed : casadi.SX or float, optional
            ∂expr/∂allowed, per unit of ``row.unit`` (the unit its name gives).
        value : casadi.SX or float, optional
            The bounded quantity, in the unit ``row.unit`` names.
        """
        self._rows.append(row)
        self._value.append(np.nan if value is None else value)
        self._g.append(expr)
        self._allowed.append(np.nan if allowed is None else allowed)
        self._dgda.append(0.0 if dg_dallowed is None else dg_dallowed)

    def minimize(self, expr: Any) -> None:
        """Set the objective (to minimise).

        Parameters
        ----------
        expr : casadi.SX
            Objective to minimise, scaled (dimensionless, O(1)).
        """
        self._f = expr

    def compile(self, options: Mapping[str, Any]) -> CompiledNLP:
        """The IPOPT solver of everything declared so far.

        Parameters
        ----------
        options : mapping
            ``casadi.nlpsol`` / IPOPT options (objects by option name).

        Returns
        -------
        CompiledNLP
            The compiled problem.
        """
        if self._f is None:
            raise ValueError("no objective")
        x = ca.vertcat(*self._xsym)
        p = ca.vertcat(*(s for s, _ in self._params.values())) if self._params else ca.SX(0, 1)
        g = ca.vertcat(*self._g) if self._g else ca.SX(0, 1)
        # one node per distinct subexpression (the rows share the thermal solves and the
        # torque model): the same values with about half the operations, and derivatives
        # (IPOPT's Jacobian and Hessian) built on the smaller graph
        fg = ca.cse(ca.vertcat(ca.SX(self._f), g))
        problem = {"x": x, "p": p, "f": fg[0], "g": fg[1:]}
        solver = ca.nlpsol("spiralcap", "ipopt", problem, options)
        lam = ca.SX.sym("lam", g.shape[0])
        lagrangian = self._f + ca.dot(lam, g)
        # d(optimal objective)/d p = ∂L/∂p at the solution (envelope theorem)
        dldp = ca.Function("dldp", [x, p, lam], [ca.gradient(lagrangian, p)])
        allowed = ca.Function(
            "allowed",
            [x, p],
            [ca.vertcat(*self._allowed), ca.vertcat(*self._dgda), ca.vertcat(*self._value)],
        )
        funcs = ca.Function("fg", [x, p], [self._f, g])
        start = ca.Function("start", [x, p], [ca.vertcat(*self._start)])
        return CompiledNLP(
            solver,
            tuple(self._vars),
            dict(self._params),
            tuple(self._rows),
            dldp,
            allowed,
            funcs,
            start,
            problem,
        )


@dataclass(frozen=True)
class Solution:
    """One IPOPT solve, readable by name (physical units for variables).

    Attributes
    ----------
    nlp : CompiledNLP
        The problem solved.
    x_scaled : ndarray
        Scaled variables at the solution, dimensionless.
    p : ndarray
        Parameter vector, each entry in the unit its parameter's name carries.
    f : float
        Objective (scaled, dimensionless).
    g : ndarray
        Rows (scaled, dimensionless).
    lam_g, lam_x : ndarray
        Multipliers of the rows and of the scaled variable bounds, dimensionless.
    status : str
        IPOPT's return status.
    iterations : int
        IPOPT iterations, count.
    """

    nlp: CompiledNLP
    x_scaled: np.ndarray
    p: np.ndarray
    f: float
    g: np.ndarray
    lam_g: np.ndarray
    lam_x: np.ndarray
    status: str
    iterations: int

    @property
    def success(self) -> bool:
        """IPOPT converged (to tolerance or to the acceptable level)."""
        return self.status in ("Solve_Succeeded", "Solved_To_Acceptable_Level")

    def value(self, name: str) -> float:
        """A variable's value, physical units.

        Parameters
        ----------
        name : str
            Variable name.

        Returns
        -------
        float
            Its value, in the unit its name carries.
        """
        i = self.nlp.var_index[name]
        return float(self.x_scaled[i] * self.nlp.variables[i].ref)

    def values(self) -> dict[str, float]:
        """Every variable, physical units.

        Returns
        -------
        dict of str to float
            Every variable's value, in the unit its name carries.
        """
        return {v.name: self.value(v.name) for v in self.nlp.variables}

    def bound_multiplier(self, name: str) -> float:
        """d f / d (upper bound) = -lam_x / ref (per physical unit); sign: >0 at the upper.

        Parameters
        ----------
        name : str
            Variable name.

        Returns
        -------
        float
            Scaled objective per unit of the variable (the unit its name carries).
        """
        i = self.nlp.var_index[name]
        return float(self.lam_x[i] / self.nlp.variables[i].ref)

    def allowed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every row's allowed value (NaN where none), ∂g/∂allowed and bounded value.

        Returns
        -------
        allowed : ndarray
            Each row's bound, in the unit its row names (NaN: none).
        dg_dallowed : ndarray
            ∂g/∂allowed of each row, per unit its row names.
        value : ndarray
            Each row's bounded quantity, in the unit its row names.
        """
        a, d, v = self.nlp.allowed(self.x_scaled, self.p)
        return np.asarray(a).ravel(), np.asarray(d).ravel(), np.asarray(v).ravel()

    def row_sensitivities(self) -> np.ndarray:
        """d f / d (allowed value of row i) through row i alone: lam_i ∂g_i/∂allowed_i.

        Returns
        -------
        ndarray
            Scaled objective per unit of each row's bound (the unit its row names).
        """
        return self.lam_g * self.allowed()[1]

    def parameter_sensitivity(self, name: str) -> np.ndarray:
        """d f / d parameter ``name`` (all rows and the objective), shape of the parameter.

        Parameters
        ----------
        name : str
            Parameter name.

        Returns
        -------
        ndarray
            Scaled objective per unit of the parameter (the unit its name carries), its shape.
        """
        full = np.asarray(self.nlp.dldp(self.x_scaled, self.p, self.lam_g)).ravel()
        return full[self.nlp.param_slices[name]]


class CompiledNLP:
    """A compiled problem: solve with parameter values by name, warm starts and new bounds.

    Parameters
    ----------
    solver : casadi.Function
        The IPOPT ``nlpsol``, object.
    variables : tuple
        The declared variables (name, scale, bounds).
    params : dict
        Parameter symbols and shapes by name (objects).
    rows : tuple of Row
        The constraint rows.
    dldp, allowed, funcs : casadi.Function
        ∂L/∂p, the rows' bounds and bounded values, and (f, g), as functions of (x, p).
    start : casadi.Function, optional
        Initial values of the variables a start does not name.
    problem : dict, optional
        The symbolic problem (for :meth:`with_options`), objects by name.
    """

    def __init__(
        self, solver, variables, params, rows, dldp, allowed, funcs, start=None, problem=None
    ) -> None:
        self.solver = solver
        self.start = start
        self._params = params
        self._problem = problem
        self.variables: tuple[_Var, ...] = variables
        self.var_index = {v.name: i for i, v in enumerate(variables)}
        self.rows: tuple[Row, ...] = rows
        self.dldp, self.allowed, self.funcs = dldp, allowed, funcs
        self.param_slices: dict[str, slice] = {}
        self.param_shapes: dict[str, tuple[int, ...]] = {}
        k = 0
        for name, (sym, shape) in params.items():
            n = int(sym.shape[0])
            self.param_slices[name] = slice(k, k + n)
            self.param_shapes[name] = shape
            k += n
        self.n_params = k

    def with_options(self, options: Mapping[str, Any]) -> CompiledNLP:
        """The same problem with an IPOPT solver of other ``options`` (warm-start settings).

        The new solver reuses this one's derivative functions (gradient, constraint Jacobian,
        Hessian of the Lagrangian: CasADi's ``cache`` option), so it costs well under a
        millisecond instead of a fresh symbolic differentiation; it evaluates the very same
        functions, so its iterates are those of a solver compiled from scratch bit for bit.

        Parameters
        ----------
        options : mapping
            IPOPT options (objects by option name).

        Returns
        -------
        CompiledNLP
            The same problem with the new solver.
        """
        if self._problem is None:
            raise ValueError("this problem was compiled without its expressions")
        derived = {name: self.solver.get_function(name) for name in self.solver.get_function()}
        solver = ca.nlpsol("spiralcap", "ipopt", self._problem, {**options, "cache": derived})
        return CompiledNLP(
            solver,
            self.variables,
            self._params,
            self.rows,
            self.dldp,
            self.allowed,
            self.funcs,
            self.start,
            self._problem,
        )

    @property
    def row_names(self) -> tuple[str, ...]:
        """Names of the constraint rows, in order."""
        return tuple(r.name for r in self.rows)

    def parameter_vector(self, values: Mapping[str, Any]) -> np.ndarray:
        """Pack named parameter values (every parameter must be given).

        Parameters
        ----------
        values : mapping of str to float or array
            Every parameter's value, in the unit its name carries.

        Returns
        -------
        ndarray
            The packed parameter vector, each entry in the unit its parameter's name carries.
        """
        p = np.empty(self.n_params)
        missing = set(self.param_slices) - set(values)
        if missing:
            raise KeyError(f"parameters not given: {sorted(missing)}")
        for name, sl in self.param_slices.items():
            p[sl] = np.asarray(values[name], dtype=float).ravel()
        return p

    def scale(self, physical: Mapping[str, float]) -> np.ndarray:
        """Physical variable values -> the scaled vector (missing names: 0).

        Parameters
        ----------
        physical : mapping of str to float
            Variable values by name, in the unit each name carries.

        Returns
        -------
        ndarray
            The scaled vector, dimensionless.
        """
        return np.array([physical.get(v.name, 0.0) / v.ref for v in self.variables])

    def scaled_start(self, x0: Mapping[str, float], p: np.ndarray) -> np.ndarray:
        """The scaled vector of physical ``x0``; variables it does not name at their declared
        ``start`` expression (auxiliary epigraph variables where their rows hold), else 0.

        Parameters
        ----------
        x0 : mapping of str to float
            Starting values by name, in the unit each name carries.
        p : ndarray
            Parameter vector, each entry in the unit its parameter's name carries.

        Returns
        -------
        ndarray
            The scaled starting vector, dimensionless.
        """
        x0s = self.scale(x0)
        missing = [i for i, v in enumerate(self.variables) if v.name not in x0]
        if missing and self.start is not None:
            x0s[missing] = np.asarray(self.start(x0s, p)).ravel()[missing]
        return x0s

    def solve(
        self,
        x0: Mapping[str, float] | Sequence[float],
        p: np.ndarray,
        bounds: Mapping[str, tuple[float, float]] | None = None,
        lam_g0: np.ndarray | None = None,
    ) -> Solution:
        """One IPOPT solve from ``x0`` (physical by name, or a scaled vector).

        Variables ``x0`` does not name start at their declared ``start`` expression (else 0).

        Parameters
        ----------
        x0 : mapping of str to float, or sequence of float
            Start: by name in the unit each name carries, or the scaled vector (dimensionless).
        p : ndarray
            Parameter vector, each entry in the unit its parameter's name carries.
        bounds : mapping of str to (float, float), optional
            Bounds replacing the declared ones, in the unit each variable's name carries.
        lam_g0 : ndarray, optional
            Warm-start row multipliers, dimensionless.

        Returns
        -------
        Solution
            The solve, readable by name.
        """
        if isinstance(x0, Mapping):
            x0s = self.scaled_start(x0, p)
        else:
            x0s = np.asarray(x0, dtype=float)
        bounds = bounds or {}
        lo = np.array([bounds.get(v.name, (v.lo, v.hi))[0] / v.ref for v in self.variables])
        hi = np.array([bounds.get(v.name, (v.lo, v.hi))[1] / v.ref for v in self.variables])
        kw: dict[str, Any] = {}
        if lam_g0 is not None:
            kw["lam_g0"] = lam_g0
        sol = self.solver(x0=x0s, p=p, lbx=lo, ubx=hi, lbg=-np.inf, ubg=0.0, **kw)
        st = self.solver.stats()
        if st["return_status"] in INTERRUPTED:
            raise SolveInterrupted(str(st["return_status"]))
        return Solution(
            self,
            np.asarray(sol["x"]).ravel(),
            np.asarray(p, dtype=float),
            float(sol["f"]),
            np.asarray(sol["g"]).ravel(),
            np.asarray(sol["lam_g"]).ravel(),
            np.asarray(sol["lam_x"]).ravel(),
            str(st["return_status"]),
            int(st.get("iter_count", 0)),
        )

    def evaluate(self, x_scaled: Sequence[float], p: np.ndarray) -> tuple[float, np.ndarray]:
        """Objective and rows at a scaled point (numbers).

        Parameters
        ----------
        x_scaled : sequence of float
            Scaled variables, dimensionless.
        p : ndarray
            Parameter vector, each entry in the unit its parameter's name carries.

        Returns
        -------
        f : float
            Objective, scaled (dimensionless).
        g : ndarray
            Rows, scaled (dimensionless).
        """
        f, g = self.funcs(np.asarray(x_scaled, dtype=float), p)
        return float(f), np.asarray(g).ravel()
