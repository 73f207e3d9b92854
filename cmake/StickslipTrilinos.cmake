# Trilinos from Debian (13.2): placeholder, filled by the bridge work.
