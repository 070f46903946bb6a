"""The one signature convention of the estimators: the model orders (``na``, ``nb``) by
position, every other parameter by keyword only, with the same name and meaning in every
estimator (``delay``, ``gamma``, ``sigma2``, ``engine``, ``prototypes``, ``random_state``).

scikit-learn reads an estimator's parameters from the signature of its ``__init__``, which
may not take ``*args`` (``BaseEstimator.get_params``); a plain keyword-only signature would
let Python refuse an old positional call with "takes from 1 to 3 positional arguments but
6 were given", which names no parameter.  :func:`orders_positional` wraps ``__init__`` so
that such a call is refused with the parameter named and the call written with keywords,
while ``inspect.signature`` (which follows ``__wrapped__``) still shows the keyword-only
signature scikit-learn needs.
"""

from __future__ import annotations

import functools
import inspect

from certkit.errors import KeywordArgumentError, shown

_POSITIONAL = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)


def orders_positional(earlier: tuple[str, ...] | None = None):
    """Decorate an estimator's ``__init__`` whose only positional parameters are its orders.

    Parameters
    ----------
    earlier : tuple of str, optional
        The parameters that followed the positional ones in the estimator's earlier
        signature, in that order (what an old positional call meant); default the
        keyword-only parameters in their order.

    Returns
    -------
    callable
        A decorator; the decorated ``__init__`` raises
        :class:`certkit.errors.KeywordArgumentError` when given more positional arguments
        than there are orders.
    """
    def decorate(init):
        parameters = list(inspect.signature(init).parameters.values())[1:]   # without self
        positional = [p.name for p in parameters if p.kind in _POSITIONAL]
        keyword = [p.name for p in parameters if p.kind == inspect.Parameter.KEYWORD_ONLY]
        meanings = tuple(keyword if earlier is None else earlier)

        @functools.wraps(init)
        def checked(self, *args, **kwargs):
            if len(args) > len(positional):
                raise _positional_error(type(self).__name__, positional, keyword, meanings,
                                        args, kwargs)
            init(self, *args, **kwargs)

        return checked

    return decorate


def _positional_error(cls: str, positional: list[str], keyword: list[str],
                      meanings: tuple[str, ...], args: tuple, kwargs: dict
                      ) -> KeywordArgumentError:
    extra = args[len(positional):]
    meant = [meanings[i] if i < len(meanings) else "?" for i in range(len(extra))]
    call = ", ".join([shown(a) for a in args[:len(positional)]]
                     + [f"{name}={shown(value)}" for name, value in zip(meant, extra)]
                     + [f"{name}={shown(value)}" for name, value in kwargs.items()])
    takes = (f"takes only the orders {', '.join(positional)} by position, every other "
             f"parameter by keyword" if positional else "takes every parameter by keyword")
    message = (f"{cls} {takes}; found {len(args)} positional arguments: pass "
               f"{', '.join(meant)} by keyword: {cls}({call})")
    if list(meanings[:len(extra)]) != keyword[:len(extra)]:
        message += (f" (what those places meant in {cls}'s earlier signature; if you meant "
                    f"another parameter, name it: {', '.join(keyword[:4])}, …)")
    return KeywordArgumentError(", ".join(meant), message)
