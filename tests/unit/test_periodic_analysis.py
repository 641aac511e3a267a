"""The conversion of a case's MechanicalSystem with Coulomb contacts into the event-driven
CoulombSystem used by ``[analysis.periodic_orbit]`` (rigid stick, per-row contacts)."""

import numpy as np
import pytest

from fricdamp.cases.periodic import coulomb_system
from fricdamp.contact import Jenkins
from fricdamp.contact.coulomb import Coulomb
from fricdamp.errors import CaseError
from fricdamp.structure import ContactElement, HarmonicLoad, chain


def test_rows_loads_and_coefficients_are_carried_over():
    """A relative contact (u = q1 - q2) and a two-row element to ground become three friction
    directions with their own N, mu_s, mu_d; the penalty stiffness is not used, the load
    replaced."""
    between = ContactElement(Coulomb(1e6, 2.0, 1.2, 1.0), [[1.0, -1.0, 0.0]], name="b")
    ground = ContactElement(Coulomb(1e5, [1.0, 3.0], 0.5, 0.4, n_contacts=2),
                            [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], name="g")
    s = chain([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], contacts=(between, ground))
    cs = coulomb_system(s, HarmonicLoad([1.0, 0.0, 0.0], 2.0))
    np.testing.assert_array_equal(cs.directions, [[1, -1, 0], [0, 1, 0], [0, 0, 1]])
    np.testing.assert_array_equal(cs.normal_load, [2.0, 1.0, 3.0])
    np.testing.assert_array_equal(cs.mu_static, [1.2, 0.5, 0.5])
    np.testing.assert_array_equal(cs.mu_sliding, [1.0, 0.4, 0.4])
    assert cs.contact_names == ("b", "g[1]", "g[2]")
    assert not cs.system.contacts
    assert cs.linear_form().frequencies.tolist() == [2.0]


@pytest.mark.parametrize(("contact", "words"), [
    (ContactElement(Jenkins(1e4, 1.0), [[1.0]]), "type = \"coulomb\""),
    (ContactElement(Coulomb(1e4, 1.0, 0.5, 0.3, 2.0), [[1.0]]), "decay_s_per_m"),
])
def test_other_laws_are_refused(contact, words):
    with pytest.raises(CaseError, match=words):
        coulomb_system(chain([1.0], [1.0], contacts=(contact,)))


def test_no_contact_is_refused():
    with pytest.raises(CaseError, match="at least one"):
        coulomb_system(chain([1.0], [1.0]))
