/* Placeholder until the sk observable tests land: reports "skipped" to meson (exit 77). */
int main(void) { return 77; }
