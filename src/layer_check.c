/* An empty program that meson.build links with the whole of one layer and only the layers below
 * it: a call from a layer to one above it is an undefined reference, so the build fails. */
int main(void) { return 0; }
