//! Rod energies on EoL/EIL yarns (seed 000 and Cirio 2014/2017).
