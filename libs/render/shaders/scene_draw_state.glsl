const bool u_has_texture = %s;
const int u_alpha_mode = %d;     // 0 opaque, 1 mask, 2 blend
const bool u_lit = %s;
const bool u_has_normals = %s;
const bool u_two_sided = %s;     // glTF doubleSided triangles: a back face uses the reversed normal
const bool u_cull_in_shader = %s;  // single-sided triangles of a mirrored instance: discard back faces
const bool u_round_points = %s;
const bool u_line_copies = %s;    // LINES standing for coincident copies: alpha 1 - (1 - a)^copies
