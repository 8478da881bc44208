"""Published reference values the report sets our numbers beside.

Tables 1 and 2 of Passigato et al. 2023 come from :mod:`motoflex_ros.structures.paper_tables`;
the Whipple benchmark eigenvalues are from Meijaard, Papadopoulos, Ruina, Schwab, "Linearized
dynamics equations for the balance and steer of a bicycle: a benchmark and review", Proc. R.
Soc. A 463 (2007) 1955-1982 ([Meijaard 2007] in docs/references.md).
"""

__all__ = ["meijaard2007_eigenvalues"]


def meijaard2007_eigenvalues():
    """Whipple benchmark eigenvalues [1/s] at 5 and 10 m/s: {speed_mps: {name: complex}}.

    The weave pair is given by its upper member (Im > 0); capsize and castering are real.
    """
    return {5.0: {"weave": complex(-0.77534188219585, 4.46486771378823),
                  "capsize": complex(-0.32286642900409, 0.0),
                  "castering": complex(-14.07838969279820, 0.0)},
            10.0: {"weave": complex(-3.72016840437287, 10.90681139476287),
                   "capsize": complex(0.16105338653172, 0.0),
                   "castering": complex(-24.62459635017404, 0.0)}}
