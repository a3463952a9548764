"""Published tissue parameter sets, one module per source (values with units in key names)."""

from torque_model.parameters.zhou2013 import check_parameter_set

__all__ = ["check_parameter_set"]
