"""A sand bed below particle scale: a height field z_b(x) moved by a bed-load law (Shields
threshold, Meyer-Peter & Mueller or Nielsen flux, saturation length), Exner in conservative
finite volumes and avalanching at the angle of repose, under the SPH water."""
