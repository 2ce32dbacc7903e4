"""The ``Seamless AO`` shader node group and material hookup."""
