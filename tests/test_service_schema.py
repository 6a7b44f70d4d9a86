"""schemathesis against the served OpenAPI schema: generated requests (valid and not) never get
a 500, and every response matches the schema. Bounded: a few dozen examples per operation."""
import pytest

schemathesis = pytest.importorskip("schemathesis")
from hypothesis import HealthCheck, settings  # noqa: E402


@pytest.fixture(scope="module")
def api_schema(served):
    return schemathesis.openapi.from_url(served + "/openapi.json")


schema = schemathesis.pytest.from_fixture("api_schema")


@schema.parametrize()
@settings(max_examples=30, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
def test_api_conforms(case):
    case.call_and_validate(timeout=60)
