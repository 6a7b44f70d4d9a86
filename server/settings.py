"""The service's settings, read from environment variables once when the app is made.

| variable | default | meaning |
|---|---|---|
| GRASPFORCE_TOKEN | unset | if set, /v1/* requires `Authorization: Bearer <token>` |
| GRASPFORCE_CORS_ORIGINS | unset | comma-separated origins allowed by CORS; unset: no CORS headers |
| GRASPFORCE_MAX_BODY_BYTES | 4194304 | larger request bodies are refused with 413 before any work |
| GRASPFORCE_MAX_CONTACTS | 64 | contacts in one grasp |
| GRASPFORCE_MAX_BATCH | 20000 | wrenches in one batch request |
| GRASPFORCE_MAX_SET_LEAVES | 256 | primitive sets in one set description |
| GRASPFORCE_THREADS | CPU count | threads that run the solves (the compiled core releases the GIL) |
"""
import os
from dataclasses import dataclass, field


def _int(name, default, minimum=1):
    raw = os.environ.get(name)
    if raw is None or raw == "":
        return default
    try:
        value = int(raw)
    except ValueError:
        raise ValueError(f"{name}: must be an integer, got {raw!r}") from None
    if value < minimum:
        raise ValueError(f"{name}: must be >= {minimum}, got {value}")
    return value


@dataclass(frozen=True)
class Settings:
    token: str | None = None
    cors_origins: tuple = ()
    max_body_bytes: int = 4 * 1024 * 1024
    max_contacts: int = 64
    max_batch: int = 20000
    max_set_leaves: int = 256
    threads: int = field(default_factory=lambda: os.cpu_count() or 1)

    @classmethod
    def from_env(cls):
        origins = tuple(o.strip() for o in os.environ.get("GRASPFORCE_CORS_ORIGINS", "").split(",")
                        if o.strip())
        return cls(token=os.environ.get("GRASPFORCE_TOKEN") or None, cors_origins=origins,
                   max_body_bytes=_int("GRASPFORCE_MAX_BODY_BYTES", cls.max_body_bytes),
                   max_contacts=_int("GRASPFORCE_MAX_CONTACTS", cls.max_contacts),
                   max_batch=_int("GRASPFORCE_MAX_BATCH", cls.max_batch),
                   max_set_leaves=_int("GRASPFORCE_MAX_SET_LEAVES", cls.max_set_leaves),
                   threads=_int("GRASPFORCE_THREADS", os.cpu_count() or 1))


# the settings of the app being served: the request models' validators read their limits here
current = Settings()
