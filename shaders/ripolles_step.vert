// Ripolles et al., the step's vertex stage: nothing; each point stands for one leaf, which
// ripolles_step.geom reads by its primitive index.
void main() { gl_Position = vec4(0.0); }
