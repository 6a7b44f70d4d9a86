"""The graspforce service: a FastAPI app over the library (server.app.create_app).

Start it with `graspforce serve` (127.0.0.1:8000), or `uvicorn --factory server:create_app`.
"""
from .app import create_app

__all__ = ["create_app"]
