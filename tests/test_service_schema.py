"""schemathesis against the served OpenAPI schema: generated requests, valid and not, never get a
500, requests that break the schema are refused, and every response matches the schema.
Bounded to a few examples per operation so the suite stays fast. Not checked: that every
schema-valid request is accepted, since some rules are the library's and no JSON Schema
states them (a nonzero normal, a proper rotation, a set's dimensions agreeing); those are 422s
naming the field and the rule (tests/test_service.py)."""
import pytest

schemathesis = pytest.importorskip("schemathesis")
from hypothesis import HealthCheck, settings  # noqa: E402
from schemathesis.checks import positive_data_acceptance  # noqa: E402
from schemathesis.config import SchemathesisConfig  # noqa: E402

EXAMPLES = 40


@pytest.fixture(scope="module")
def api_schema(served):
    # the examples and fuzzing phases, valid and invalid data; the coverage phase's boundary
    # values of this schema (64 nested sets of 10,000 vertices) take minutes to generate
    config = SchemathesisConfig.from_dict({
        "phases": {"coverage": {"enabled": False}},
        "generation": {"max-examples": EXAMPLES, "deterministic": True}})
    return schemathesis.openapi.from_url(served + "/openapi.json", config=config)


schema = schemathesis.pytest.from_fixture("api_schema")


@schema.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
def test_api_conforms(case):
    case.call_and_validate(timeout=60, excluded_checks=[positive_data_acceptance])
