"""Manufactured solutions used by the tests (they live in :mod:`ngdgfric.studies.manufactured`)."""

from ngdgfric.studies.manufactured import (  # noqa: F401
    contact_manufactured,
    elasticity_manufactured,
    friction_manufactured,
    incompressible_contact_manufactured,
)
