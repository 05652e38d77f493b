"""The isolated frame's transient result as a pandas DataFrame / xarray Dataset: every history
(isolator slip, normal and friction forces, slip modes, generalised coordinates) bit for bit,
indexed by the output times, the summary (units in its names) as attributes."""

from __future__ import annotations

import math

import numpy as np

import nsdyn
from nsdyn import Harmonic, Isolation, system_from_matrices


def test_to_dataframe_round_trips_the_histories(assert_round_trip):
    m1, m2, k2, c2 = 1.0, 1.0, (2 * math.pi) ** 2, 0.2
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.1, law="arctan", eps=100.0)
    sysm = system_from_matrices(
        [[m1, 0.0], [0.0, m2]], [[c2, -c2], [-c2, c2]], [[k2, -k2], [-k2, k2]], iso_dofs=[0],
        influence=[1.0, 1.0], isolation=iso, weight=(m1 + m2) * iso.g, levels=[[0], [1]],
    )  # fmt: skip
    res = nsdyn.simulate(sysm, Harmonic(2.0, 1.0), t_end=1.0, method="radau")
    assert_round_trip(res)
    df = res.to_dataframe()
    # the isolator slip column is the summary's peak (its definition: max |x_iso| over the grid)
    assert np.max(np.abs(df["x_iso_0_m"].to_numpy())) == df.attrs["x_iso_max_m"]
