"""Dask's executor of an existing cluster (``--scheduler``) for
:func:`~deck_emulator.studies.distributed.run_scenes`, once a Dask scheduler answers there."""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import dataclasses

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.defaults import WORKER_WAIT_S


class ClusterError(UsageError, ValueError):
    """No Dask scheduler can be reached at the address given: exit status 2."""


@dataclasses.dataclass(frozen=True)
class Scheduler:
    """An external Dask cluster's address and how long a run waits for a worker."""

    address: str
    worker_wait_s: float = WORKER_WAIT_S

    def __str__(self) -> str:
        return self.address


@contextlib.contextmanager
def dask_executor(scheduler: str, worker_wait_s: float):
    """``(executor, its workers, alive())`` of the Dask cluster at ``scheduler`` (left
    running), once it has a worker; what is left at the end (an error, a Ctrl-C) is
    cancelled."""
    from distributed import Client

    _reach(scheduler)
    try:
        client = Client(scheduler, timeout=defaults.SCHEDULER_CONNECT_S)
    except (ValueError, OSError, TimeoutError) as exc:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ClusterError(f"--scheduler {scheduler}: cannot reach the scheduler: "
                           f"{why}") from None
    try:
        try:
            client.wait_for_workers(1, timeout=worker_wait_s)
        except (TimeoutError, OSError):
            raise RunFailed(f"the scheduler at {scheduler} has no worker: none joined in "
                            f"{worker_wait_s:g} s") from None
        executor = client.get_executor(pure=False)
        try:
            yield executor, _workers(client) or 1, lambda: _workers(client) > 0
        finally:
            executor.shutdown(wait=False)  # what is left (an error, a Ctrl-C) is cancelled
    finally:
        with contextlib.suppress(Exception):
            client.close()


def _workers(client) -> int:
    """The cluster's workers now; a scheduler gone (Dask's errors are OSErrors) has none."""
    try:
        return len(client.nthreads())
    except OSError:
        return 0


def _reach(address: str) -> None:
    """:class:`ClusterError` in one line unless a Dask scheduler answers at ``address``: a
    plain TCP connection first (a refusal is told at once, whatever the load; Dask's connect
    retries it until its time-out), then Dask's ``connect`` and handshake, bounded (Dask
    leaves the handshake unbounded: a silent port held a sweep for ever), then the
    scheduler's identity.  ``inproc://`` is this process's own cluster: not asked."""
    import asyncio
    import socket

    from distributed.comm import connect, parse_address, parse_host_port
    from distributed.security import Security

    where, bound = f"--scheduler {address}", defaults.SCHEDULER_CONNECT_S
    try:
        scheme, location = parse_address(address)
    except (ValueError, TypeError) as exc:
        raise ClusterError(f"{where}: this install cannot connect so ({exc}); give "
                           "tcp://HOST:PORT") from None
    if scheme == "inproc":
        return
    args = Security().get_connection_args("client")  # Dask's TLS settings, if any
    if scheme in ("tls", "wss") and args.get("ssl_context") is None:
        raise ClusterError(f"{where}: {scheme}:// needs Dask's TLS settings (distributed.comm."
                           "tls.ca-file, .client.cert, .client.key) and none are set")
    if scheme in ("tcp", "tls", "ws", "wss"):
        try:
            with socket.create_connection(parse_host_port(location), timeout=bound):
                pass
        except TimeoutError:
            raise ClusterError(f"{where}: no connection in {bound:g} s") from None
        except (OSError, ValueError) as exc:  # refused, no such host, not HOST:PORT
            raise ClusterError(f"{where}: nothing listens there ({exc})") from None

    async def identity():
        comm = await connect(address, timeout=bound, deserialize=True, **args)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    async def bounded():
        return await asyncio.wait_for(identity(), 2 * bound)

    with cf.ThreadPoolExecutor(1) as pool:  # its own event loop, in any caller
        try:
            who = pool.submit(asyncio.run, bounded()).result()
        except asyncio.TimeoutError:  # connected, then nothing
            raise ClusterError(f"{where}: something took the connection and said nothing a "
                               f"Dask scheduler says in {2 * bound:g} s") from None
        except (TypeError, ImportError) as exc:  # ucx:// without its library: no connector
            raise ClusterError(f"{where}: this install cannot connect so ({exc}); give "
                               "tcp://HOST:PORT") from None
        except (OSError, ValueError) as exc:  # refused, reset, no connection in the bound
            cause = exc.__cause__ or exc
            why = str(cause).splitlines()[0][:120] if str(cause) else type(cause).__name__
            if isinstance(cause, (asyncio.TimeoutError, TimeoutError)):
                raise ClusterError(f"{where}: no connection in {bound:g} s") from None
            raise ClusterError(f"{where}: {'not an address' if isinstance(cause, ValueError) else 'nothing listens there'} ({why})") from None
        except Exception:  # noqa: BLE001 - bytes that are not Dask's, whatever they raise
            raise ClusterError(f"{where}: something answered there, not in Dask's protocol "
                               "(not a Dask scheduler)") from None
    kind = who.get("type") if isinstance(who, dict) else None
    if kind != "Scheduler":
        raise ClusterError(f"{where}: {'a Dask ' + kind if kind else 'something'} answered "
                           "there, not a Dask scheduler")
