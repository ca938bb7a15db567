# The plane-strain continuum of the validate cantilever (lab/src/validate/cantilever.rs): a Q9
# (biquadratic) finite-element solution of the beam clamped with u = 0 on x = 0 under its own
# weight, on three meshes, printed as w / w_Euler-Bernoulli along the centreline. It separates
# the discretisation error of the SPH beam from what the continuum itself adds to
# Euler-Bernoulli (shear, the clamp face restraining the cross-section). Needs numpy, scipy:
#   python3 lab/reference/cantilever_fem.py 0.5 1.0
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as sl, sys
E, nu, rho, g, t = 1e8, 0.3, 2700.0, 0.01, 0.1
def run(L, nx, ny):
    Nx, Ny = 2*nx+1, 2*ny+1
    xs = np.linspace(0, L, Nx); ys = np.linspace(-t/2, t/2, Ny)
    nid = lambda i, j: j*Nx + i
    D = E/((1+nu)*(1-2*nu))*np.array([[1-nu,nu,0],[nu,1-nu,0],[0,0,(1-2*nu)/2]])
    gp, gw = np.polynomial.legendre.leggauss(3)
    def sf(r):  # 1D quadratic on [-1,1], nodes -1,0,1
        return np.array([r*(r-1)/2, 1-r*r, r*(r+1)/2]), np.array([r-0.5, -2*r, r+0.5])
    hx, hy = L/nx, t/ny
    Ke = np.zeros((18,18)); fe = np.zeros(18)
    for a, wa in zip(gp, gw):
        for b, wb in zip(gp, gw):
            Na, dNa = sf(a); Nb, dNb = sf(b)
            B = np.zeros((3,18)); N = np.zeros(9)
            for j in range(3):
                for i in range(3):
                    k = j*3+i
                    dx = dNa[i]*Nb[j]*2/hx; dy = Na[i]*dNb[j]*2/hy
                    B[0,2*k] = dx; B[1,2*k+1] = dy; B[2,2*k] = dy; B[2,2*k+1] = dx
                    N[k] = Na[i]*Nb[j]
            w = wa*wb*hx*hy/4
            Ke += B.T@D@B*w
            fe[1::2] += -rho*g*N*w
    rows, cols, vals = [], [], []; F = np.zeros(2*Nx*Ny)
    for ey in range(ny):
        for ex in range(nx):
            dofs = []
            for j in range(3):
                for i in range(3):
                    n = nid(2*ex+i, 2*ey+j); dofs += [2*n, 2*n+1]
            dofs = np.array(dofs)
            rows.append(np.repeat(dofs, 18)); cols.append(np.tile(dofs, 18)); vals.append(Ke.ravel())
            F[dofs] += fe
    K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(F.size,)*2)
    fixed = np.array([[2*nid(0,j), 2*nid(0,j)+1] for j in range(Ny)]).ravel()
    free = np.setdiff1d(np.arange(F.size), fixed)
    u = np.zeros(F.size); u[free] = sl.spsolve(K[free][:,free].tocsc(), F[free])
    v = u[1::2].reshape(Ny, Nx)[Ny//2]  # centreline
    return xs, -v
def eb(L, x):
    q = rho*g*t; I = t**3/12; Ep = E/(1-nu*nu)
    return q*x*x*(6*L*L-4*L*x+x*x)/(24*Ep*I)
for L in [float(a) for a in sys.argv[1:]] or [0.5, 1.0]:
    for n in [(40, 4), (80, 8), (160, 16)]:
        nx, ny = int(n[0]*L/0.5), n[1]
        xs, w = run(L, nx, ny)
        print(f"L={L} mesh {nx}x{ny}: tip w/w_EB {w[-1]/eb(L, L):.5f}; at x=L-0.1t/... profile:",
              " ".join(f"{x:.3f}:{w[k]/eb(L,x):.4f}" for k, x in list(enumerate(xs))[len(xs)//12::len(xs)//6]))
