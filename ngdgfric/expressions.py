"""Safe arithmetic expressions in ``x`` and ``y`` for the data of a problem file (:mod:`ngdgfric.problem_file`).

An expression is a number or a string in ``x`` and ``y``: numbers, ``pi``, ``+ - * / **``, unary ``-``, the
functions of ``FUNCTIONS`` (one argument: ``sin cos tan exp log sqrt atan abs``, and ``step(t)``, 1 for
t > 0 and 0 otherwise), ``min(a, b)``, ``max(a, b)`` and ``if(condition, a, b)`` with one comparison ``<``,
``<=``, ``>`` or ``>=`` as the condition (``if(x > 1.5, -300, 0)``).  ``parse_expression`` parses it with
``ast`` and turns it into an NGSolve CoefficientFunction (conditions by ``ngs.IfPos``); nothing is ever passed
to ``eval``.  Constant expressions stay numbers.  Anything outside this grammar is a ValueError saying what is
not allowed.
"""

import ast
import math
import operator
import re
import threading
import warnings

import ngsolve as ngs

__all__ = ["parse_expression", "FUNCTIONS", "BINARY", "IF", "ALLOWED_FUNCTIONS", "MAX_LENGTH"]


def _cf_abs(value):
    return ngs.IfPos(value, value, -value)


def _if_positive(value, then, otherwise):
    """``then`` where ``value`` > 0, else ``otherwise``: by Python on numbers, by ``ngs.IfPos`` on
    CoefficientFunctions."""
    if isinstance(value, float):
        return then if value > 0 else otherwise
    return ngs.IfPos(value, then, otherwise)


# name: (on numbers, on CoefficientFunctions); one argument each
FUNCTIONS = {
    "sin": (math.sin, ngs.sin), "cos": (math.cos, ngs.cos), "tan": (math.tan, ngs.tan),
    "exp": (math.exp, ngs.exp), "log": (math.log, ngs.log), "sqrt": (math.sqrt, ngs.sqrt),
    "atan": (math.atan, ngs.atan), "abs": (abs, _cf_abs),
    "step": (lambda t: 1.0 if t > 0 else 0.0, lambda t: ngs.IfPos(t, 1.0, 0.0)),
}
# two arguments, on numbers and CoefficientFunctions alike
BINARY = {"min": lambda a, b: _if_positive(a - b, b, a), "max": lambda a, b: _if_positive(a - b, a, b)}
IF = "if"  # if(condition, a, b); a keyword in Python, so the text calls _IF_NAME instead before parsing
_IF_NAME = "if_"
_IF_CALL = re.compile(r"(?<![\w.])if(?=\s*\()")
_IF_NAME_USED = re.compile(r"(?<![\w.])if_(?!\w)")
ALLOWED_FUNCTIONS = ", ".join(sorted([*FUNCTIONS, *BINARY, IF]))
# a comparison: (on numbers, on CoefficientFunctions as (the difference d of its sides, whether it holds where
# d <= 0 rather than where d > 0) for ngs.IfPos)
COMPARISONS = {ast.Gt: (operator.gt, lambda a, b: a - b, False), ast.Lt: (operator.lt, lambda a, b: b - a, False),
               ast.GtE: (operator.ge, lambda a, b: b - a, True), ast.LtE: (operator.le, lambda a, b: a - b, True)}
VARIABLES = {"x": ngs.x, "y": ngs.y, "pi": math.pi}


def _power(base, exponent):
    """base ** exponent; an integer exponent on a CoefficientFunction by repeated multiplication
    (NGSolve's vectorised pow computes exp(e log b), NaN for b < 0: (x - 1)**2 was NaN for x < 1)."""
    if isinstance(base, ngs.CoefficientFunction) and isinstance(exponent, float) and exponent.is_integer() \
            and 0 < abs(exponent) <= 64:
        result, factor, n = None, base, int(abs(exponent))
        while n:
            if n & 1:
                result = factor if result is None else result * factor
            factor, n = factor * factor, n >> 1
        return result if exponent > 0 else 1 / result
    return operator.pow(base, exponent)


OPERATORS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
             ast.Pow: _power}
MAX_LENGTH = 1000


def parse_expression(text):
    """A number or a scalar CoefficientFunction of x, y from a safe arithmetic expression.

    ValueError (saying what is not allowed) for anything outside the grammar of the module docstring.
    Parsed and evaluated in a thread of its own, whose Python stack starts empty: how deeply an
    expression may nest (Python's recursion limit) does not depend on how deep the caller's stack is.
    """
    outcome = {}

    def run():
        try:
            outcome["value"] = _parse(text)
        except Exception as exc:  # handed to the caller's thread below
            outcome["error"] = exc

    thread = threading.Thread(target=run, name="ngdgfric-expression")
    thread.start()
    thread.join()
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


def _parse(text):
    if len(text) > MAX_LENGTH:
        raise ValueError(f"expression longer than {MAX_LENGTH} characters")
    if _IF_NAME_USED.search(text):
        raise ValueError(f"unknown name {_IF_NAME!r} (the condition function is called if)")
    try:
        with warnings.catch_warnings():  # "invalid decimal literal" for 2x: the SyntaxError that follows says it
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(_IF_CALL.sub(_IF_NAME, text.strip()), mode="eval")
    except (SyntaxError, RecursionError, MemoryError) as exc:
        raise ValueError("not a valid expression") from exc
    try:
        value = _evaluate(tree.body)
    except ZeroDivisionError as exc:
        raise ValueError("division by zero") from exc
    except (OverflowError, RecursionError) as exc:
        raise ValueError("overflow (number too large or expression too deep)") from exc
    if isinstance(value, complex) or (isinstance(value, float) and not math.isfinite(value)):
        raise ValueError(f"evaluates to {value}, not a finite real number")
    return value


def _shown(node):
    """The source of a node as the user wrote it (if(...), not the internal name)."""
    return re.sub(rf"(?<![\w.]){_IF_NAME}\(", f"{IF}(", ast.unparse(node))


def _evaluate(node):
    if isinstance(node, ast.Constant):
        if isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            value = float(node.value)  # floats only: 10**10**10 overflows instead of hanging
            if math.isfinite(value):
                return value
        raise ValueError(f"constant {node.value!r} is not a finite real number")
    if isinstance(node, ast.Name):
        if node.id not in VARIABLES:
            raise ValueError(f"unknown name {node.id!r} (allowed: x, y, pi)")
        return VARIABLES[node.id]
    if isinstance(node, ast.BinOp) and type(node.op) in OPERATORS:
        value = OPERATORS[type(node.op)](_evaluate(node.left), _evaluate(node.right))
        if isinstance(value, complex):
            raise ValueError(f"{_shown(node)!r} is not a real number")
        return value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        operand = _evaluate(node.operand)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.Call):
        return _call(node)
    if isinstance(node, ast.Compare):
        raise ValueError(f"the comparison {_shown(node)!r} is only allowed as the condition of if(condition, a, b)")
    if isinstance(node, ast.BoolOp):
        raise ValueError(f"{_shown(node)!r}: 'and' and 'or' are not allowed (nest if(...) instead)")
    raise ValueError(f"{_shown(node)!r} is not allowed")


def _call(node):
    """A function call: one of FUNCTIONS, BINARY or if(condition, a, b)."""
    name = node.func.id if isinstance(node.func, ast.Name) else _shown(node.func)
    name = IF if name == _IF_NAME else name
    count = {IF: 3, **dict.fromkeys(BINARY, 2)}.get(name, 1)
    if name not in FUNCTIONS and name not in BINARY and name != IF:
        raise ValueError(f"function {name!r} is not allowed (allowed: {ALLOWED_FUNCTIONS})")
    if node.keywords:
        raise ValueError(f"{name} takes no keyword arguments")
    if any(isinstance(a, ast.Starred) for a in node.args):
        raise ValueError(f"{name}: *arguments are not allowed")
    if len(node.args) != count:
        usage = {IF: "if(condition, a, b)", "min": "min(a, b)", "max": "max(a, b)"}.get(name, f"{name}(t)")
        raise ValueError(f"{name} takes exactly {count} argument{'s' * (count > 1)}, {usage}; got {len(node.args)}")
    if name == IF:
        on_numbers, difference, negated, left, right = _condition(node.args[0])
        then, otherwise = _evaluate(node.args[1]), _evaluate(node.args[2])
        if isinstance(left, float) and isinstance(right, float):
            return then if on_numbers(left, right) else otherwise
        d = difference(left, right)
        return ngs.IfPos(d, otherwise, then) if negated else ngs.IfPos(d, then, otherwise)
    if name in BINARY:
        return BINARY[name](_evaluate(node.args[0]), _evaluate(node.args[1]))
    argument = _evaluate(node.args[0])
    on_number, on_cf = FUNCTIONS[name]
    if isinstance(argument, float):
        try:
            return float(on_number(argument))
        except ValueError as exc:  # math domain error
            raise ValueError(f"{name}({argument:g}): {exc}") from exc
    return on_cf(argument)


def _condition(node):
    """The comparison ``node`` as its row of COMPARISONS and its two sides, evaluated."""
    if isinstance(node, ast.BoolOp):
        raise ValueError(f"{_shown(node)!r}: 'and' and 'or' are not allowed (nest if(...) instead)")
    if not isinstance(node, ast.Compare):
        raise ValueError(f"the condition of if(condition, a, b) must be a comparison such as x > 1 "
                         f"(<, <=, >, >=), got {_shown(node)!r}")
    if len(node.ops) != 1:
        raise ValueError(f"{_shown(node)!r}: one comparison per condition (nest if(...) for a range)")
    if type(node.ops[0]) not in COMPARISONS:
        raise ValueError(f"{_shown(node)!r}: only <, <=, > and >= compare (== and != are fragile on "
                         f"floating-point values)")
    return *COMPARISONS[type(node.ops[0])], _evaluate(node.left), _evaluate(node.comparators[0])
