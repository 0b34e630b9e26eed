// The back faces' depth pass for the unscattered light (surface.frag, UNSCATTERED): the depth
// buffer is all it writes.
void main() {}
