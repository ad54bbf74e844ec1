// The depth pre-pass: depth only.
void main() {}
