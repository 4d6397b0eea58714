"""Numbers printed in Porwal & Tanvi, Section 6 (targets to compare with, never inputs)."""

__all__ = ["TABLES"]

# Tables 6.1 (Example 6.1) and 6.2 (Example 6.2): error and order of convergence per row h = 2^-1 ... 2^-5.
TABLES = {
    "6.1": {
        "sipg": {"error": (4.7518e-1, 2.9620e-1, 1.7708e-1, 1.0731e-1, 6.7152e-2),
                 "rate": (None, 0.6818, 0.7421, 0.7502, 0.7913)},
        "nipg": {"error": (4.8844e-1, 3.0242e-1, 1.807e-1, 1.0732e-1, 6.7186e-2),
                 "rate": (None, 0.6916, 0.7427, 0.7519, 0.7934)},
    },
    "6.2": {
        "sipg": {"error": (6.7573e-1, 4.1330e-1, 2.4171e-1, 1.4053e-1, 8.235e-2),
                 "rate": (None, 0.7091, 0.7735, 0.7824, 0.7901)},
        "nipg": {"error": (6.7731e-1, 4.1610e-1, 2.4403e-1, 1.4197e-1, 8.241e-2),
                 "rate": (None, 0.7028, 0.7698, 0.7814, 0.7896)},
    },
}
